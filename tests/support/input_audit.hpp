// What each honest client sent and what the server stepped with, for tests
// that show a hostile or passive party (an attacker, an observer) changed
// nothing in a live race: every car moved by its own client's inputs only.
//
// Why not compare with the same race run without the party? On a virtual
// clock the bots still drive from predicted worlds that depend on when
// snapshots arrive in real time, so two runs of the same race differ under
// CPU load. The inputs each car was stepped with, checked against what its
// own client sent, and the end state against the replay of those inputs, do
// not depend on timing.
#pragma once

#include "forwarding_transport.hpp"
#include "jetrace/core/hovercar.hpp"
#include "jetrace/proto/messages.hpp"
#include "jetrace/server/race_observer.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <variant>
#include <vector>

namespace jetrace::test {

/// Records the first input for each tick in the InputBatches a client sends
/// (later copies for a tick repeat it: the client's prediction ring).
class SentInputs final : public ForwardingTransport {
public:
    using ForwardingTransport::ForwardingTransport;
    bool send(net::PeerId peer, net::Channel ch, std::span<const std::uint8_t> data) override {
        proto::Message m;
        std::string why;
        if (proto::decode(data, m, why) && std::holds_alternative<proto::InputBatch>(m)) {
            const auto& b = std::get<proto::InputBatch>(m);
            for (std::size_t i = 0; i < b.inputs.size(); ++i) {
                by_tick.try_emplace(b.first_tick + static_cast<std::uint32_t>(i), b.inputs[i]);
            }
        }
        return ForwardingTransport::send(peer, ch, data);
    }
    /// Unit: one input per tick.
    std::map<std::uint32_t, Input> by_tick;
};

/// Passes everything on to `next` (if any) and keeps every slot's input of
/// every tick stepped.
class AppliedInputs final : public server::RaceObserver {
public:
    explicit AppliedInputs(server::RaceObserver* next) : next_(next) {}
    void race_started(const replay::Header& h) override {
        if (next_) next_->race_started(h);
    }
    void before_step(std::uint32_t tick, std::span<const std::uint8_t> removed,
                     std::span<const Input> inputs) override {
        by_tick[tick].assign(inputs.begin(), inputs.end());
        if (next_) next_->before_step(tick, removed, inputs);
    }
    void after_step(const WorldState& after) override {
        if (next_) next_->after_step(after);
    }
    void race_ended(const replay::Trailer& t) override {
        if (next_) next_->race_ended(t);
    }
    void stopped() override {
        if (next_) next_->stopped();
    }
    /// Every slot's input, by tick stepped.
    std::map<std::uint32_t, std::vector<Input>> by_tick;

private:
    server::RaceObserver* next_;
};

/// Checks that the car in `slot` was stepped with exactly what `sent` holds
/// for each tick, and where nothing arrived with the input before (the
/// server's repeat rule). Returns the ticks where the client's own input was used.
inline std::size_t expect_stepped_as_sent(const AppliedInputs& applied, int slot, const SentInputs& sent,
                                          const std::string& who) {
    std::size_t own = 0, mismatches = 0;
    const Input* previous = nullptr;
    for (const auto& [tick, inputs] : applied.by_tick) {
        if (slot < 0 || static_cast<std::size_t>(slot) >= inputs.size()) break;
        const Input& got = inputs[static_cast<std::size_t>(slot)];
        const auto it = sent.by_tick.find(tick);
        if (it != sent.by_tick.end()) {
            if (got == it->second) ++own;
            else if (++mismatches <= 3) ADD_FAILURE() << who << ": tick " << tick << " stepped with an input it did not send";
        } else if (previous != nullptr && !(got == *previous)) {
            if (++mismatches <= 3) ADD_FAILURE() << who << ": tick " << tick << " without an input did not repeat the last";
        }
        previous = &got;
    }
    EXPECT_EQ(mismatches, 0u) << who;
    return own;
}

}  // namespace jetrace::test
