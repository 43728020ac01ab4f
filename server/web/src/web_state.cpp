#include "web_state.hpp"

#include "game_socket.hpp"

#include <spdlog/spdlog.h>

namespace jetrace::web::detail {

WebState::Admission WebState::reserve(const std::string& address) {
    std::lock_guard lock(mutex);
    if (sockets.size() + handshaking >= config.max_sockets) {
        ++stats.full_refusals;
        ++totals.connects_refused;
        return Admission::full;
    }
    const std::size_t cap = config.max_pending_per_address;
    if (cap != 0) {
        const auto it = pending.find(address);
        if (it != pending.end() && it->second >= cap) {
            ++stats.pre_hello_refusals;
            ++totals.connects_refused;
            return Admission::pre_hello_cap;
        }
    }
    ++pending[address];
    ++handshaking;
    return Admission::open;
}

namespace {
void release(std::map<std::string, std::size_t>& pending, const std::string& address) {
    const auto it = pending.find(address);
    if (it != pending.end() && --it->second == 0) pending.erase(it);
}
}  // namespace

void WebState::abandoned(const std::string& address) {
    std::lock_guard lock(mutex);
    release(pending, address);
    --handshaking;
}

void WebState::admit(net::PeerId peer) {
    std::lock_guard lock(mutex);
    const auto it = sockets.find(peer);
    if (it == sockets.end() || it->second->admitted) return;
    it->second->admitted = true;
    release(pending, it->second->address());
}

void WebState::opened(const std::shared_ptr<GameSocket>& s) {
    std::lock_guard lock(mutex);
    const net::PeerId peer = next_peer++;
    s->set_peer(peer);
    sockets.emplace(peer, s);
    --handshaking;
    net::Event e;
    e.type = net::Event::Type::connected;
    e.peer = peer;
    events.push_back(std::move(e));
    spdlog::debug("web: socket {} from {} open", peer - kWebPeerBase, s->address());
}

void WebState::closed(const GameSocket& s, std::uint16_t close_code) {
    std::lock_guard lock(mutex);
    if (sockets.erase(s.peer()) == 0) return;
    if (!s.admitted) release(pending, s.address());
    if (close_code == kSendQueueFull) ++stats.send_queue_drops;
    if (close_code == kMalformedFrame) ++stats.malformed_drops;
    net::Event e;
    e.type = net::Event::Type::disconnected;
    e.peer = s.peer();
    e.close_code = close_code;
    events.push_back(std::move(e));
}

void WebState::received(net::PeerId peer, net::Channel channel, std::vector<std::uint8_t> data) {
    std::lock_guard lock(mutex);
    totals.bytes_received += data.size() + 1;
    ++totals.packets_received;
    net::Event e;
    e.type = net::Event::Type::received;
    e.peer = peer;
    e.channel = channel;
    e.data = std::move(data);
    events.push_back(std::move(e));
}

}  // namespace jetrace::web::detail
