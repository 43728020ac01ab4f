#include "socket_transport.hpp"

#include "jetrace/net/ws_frame.hpp"

#include <emscripten.h>

#include <map>

// The page's side (client_source.js): Module.jetraceSocket.{open, send, close}.
EM_JS(void, js_socket_open, (int id), { Module.jetraceSocket.open(id); });
EM_JS(int, js_socket_send, (int id, int channel, const std::uint8_t* data, int size), {
    return Module.jetraceSocket.send(id, channel, HEAPU8.subarray(data, data + size)) ? 1 : 0;
});
EM_JS(void, js_socket_close, (int id), { Module.jetraceSocket.close(id); });

namespace jetrace::webclient {

namespace {
std::map<int, SocketTransport*>& registry() {
    static std::map<int, SocketTransport*> sockets;
    return sockets;
}
}  // namespace

SocketTransport::SocketTransport(int id) : id_(id) {
    registry()[id] = this;
    js_socket_open(id);
}

SocketTransport::~SocketTransport() {
    registry().erase(id_);
    if (!closed_) js_socket_close(id_);
}

SocketTransport* SocketTransport::find(int id) {
    const auto it = registry().find(id);
    return it == registry().end() ? nullptr : it->second;
}

void SocketTransport::opened() {
    if (open_ || closed_) return;
    open_ = true;
    net::Event e;
    e.type = net::Event::Type::connected;
    pending_.push_back(std::move(e));
}

void SocketTransport::frame(const std::uint8_t* data, std::size_t size) {
    // The server's frames are as untrusted as any datagram: a bad channel
    // byte or an empty message is dropped here, the message itself checked
    // by the client's decoders.
    net::Channel channel{};
    std::span<const std::uint8_t> message;
    if (!open_ || closed_ || !net::read_ws_frame({data, size}, channel, message)) return;
    totals_.bytes_received += size;
    ++totals_.packets_received;
    net::Event e;
    e.type = net::Event::Type::received;
    e.channel = channel;
    e.data.assign(message.begin(), message.end());
    pending_.push_back(std::move(e));
}

void SocketTransport::closed(int code) {
    if (closed_) return;
    closed_ = true;
    open_ = false;
    net::Event e;
    e.type = net::Event::Type::disconnected;
    e.close_code = code >= 3000 && code <= 4999 ? static_cast<std::uint16_t>(code) : 0;
    pending_.push_back(std::move(e));
}

void SocketTransport::service(std::uint64_t, std::vector<net::Event>& events) {
    for (net::Event& e : pending_) events.push_back(std::move(e));
    pending_.clear();
}

bool SocketTransport::send(net::PeerId peer, net::Channel channel, std::span<const std::uint8_t> data) {
    if (peer != 0 || !open_ || data.empty()) return false;
    if (js_socket_send(id_, static_cast<int>(channel), data.data(), static_cast<int>(data.size())) == 0) return false;
    totals_.bytes_sent += data.size() + 1;
    ++totals_.packets_sent;
    return true;
}

void SocketTransport::disconnect(net::PeerId peer) {
    if (peer != 0 || closed_) return;
    js_socket_close(id_);
}

}  // namespace jetrace::webclient
