#include "join_pacing.hpp"

namespace jetrace::bot {

std::vector<std::size_t> bots_to_start(const std::vector<JoinPhase>& phase, const std::vector<std::size_t>& address,
                                       std::size_t addresses, int limit) {
    std::vector<int> joining(addresses, 0);
    const std::size_t n = phase.size() < address.size() ? phase.size() : address.size();
    for (std::size_t i = 0; i < n; ++i) {
        if (phase[i] == JoinPhase::joining && address[i] < addresses) ++joining[address[i]];
    }
    std::vector<std::size_t> start;
    for (std::size_t i = 0; i < n; ++i) {
        if (phase[i] != JoinPhase::waiting || address[i] >= addresses || joining[address[i]] >= limit) continue;
        ++joining[address[i]];
        start.push_back(i);
    }
    return start;
}

}  // namespace jetrace::bot
