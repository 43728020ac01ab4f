// UnallocatedGate: refuses players until Agones allocates the server.
#include "jetrace/ops/unallocated_gate.hpp"

#include "jetrace/proto/messages.hpp"

#include <spdlog/spdlog.h>

namespace jetrace::ops {

void UnallocatedGate::service(net::Transport& transport, std::uint64_t now_ms) {
    events_.clear();
    transport.service(now_ms, events_);
    for (const net::Event& e : events_) {
        if (e.type == net::Event::Type::connected) {
            connected_ms_[e.peer] = now_ms;
        } else if (e.type == net::Event::Type::disconnected) {
            connected_ms_.erase(e.peer);
        } else if (connected_ms_.count(e.peer) != 0) {
            proto::Message m;
            std::string error;
            if (proto::decode(e.data, m, error) && std::holds_alternative<proto::Hello>(m)) {
                ++refused_;
                spdlog::warn("refusing client {} ({}): {}", e.peer, std::get<proto::Hello>(m).name, kUnallocatedReason);
                transport.send(e.peer, net::Channel::reliable, proto::encode(proto::Refuse{
                    kUnallocatedReason, static_cast<std::uint16_t>(proto::CloseCode::refused_unallocated)}));
            }
            transport.disconnect(e.peer);
            connected_ms_.erase(e.peer);
        }
    }
    for (auto it = connected_ms_.begin(); it != connected_ms_.end();) {
        if (now_ms - it->second > hello_timeout_ms_) {
            transport.disconnect(it->first);
            it = connected_ms_.erase(it);
        } else {
            ++it;
        }
    }
    transport.flush();
}

void UnallocatedGate::close_all(net::Transport& transport) {
    for (const auto& [peer, since] : connected_ms_) transport.disconnect(peer);
    connected_ms_.clear();
    transport.flush();
}

}  // namespace jetrace::ops
