// One TCP connection to the web port, on the I/O thread: answers GET and
// HEAD from the site table (in memory: no request path reaches the file
// system) and hands an upgrade of GET /play to a GameSocket when the Origin
// is allowed and the caps let it in. Request heads and bodies are
// size-limited; anything else gets 403, 404, 405 or 503.
#pragma once

#include "web_state.hpp"

#include <boost/asio/ip/tcp.hpp>

#include <memory>
#include <string>

namespace jetrace::web::detail {

/// Starts serving `socket`.
void serve_http(boost::asio::ip::tcp::socket&& socket, WebState& state);

/// Whether a page from `origin` may open a game socket on a server the
/// page reached as `host` (the Host header): no Origin (not a browser),
/// the server's own (http:// or https:// and `host`), or one of `allowed`.
bool origin_allowed(std::string_view origin, std::string_view host, const std::vector<std::string>& allowed);

}  // namespace jetrace::web::detail
