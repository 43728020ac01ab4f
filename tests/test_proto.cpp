// jetrace::proto: every message round-trips; decoding rejects malformed,
// truncated, oversized and out-of-range bytes without crashing. The world
// payload inside snapshots: test_world_codec.cpp.
#include "jetrace/proto/messages.hpp"
#include "jetrace/proto/world_codec.hpp"
#include "jetrace_generated.h"
#include "support/test_seed.hpp"
#include "support/wire_craft.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <iostream>
#include <limits>
#include <random>
#include <tuple>

namespace jp = jetrace::proto;
namespace fb = flatbuffers;
namespace w = jetrace::wire;

namespace {

// ------------------------------------------------------------ equality

auto tie(const jp::Hello& m) {
    return std::tie(m.protocol_version, m.name, m.reconnect_token, m.connect_token, m.observe);
}
auto tie(const jp::Welcome& m) {
    return std::tie(m.protocol_version, m.slot, m.max_players, m.tick_rate_hz, m.snapshot_rate_hz, m.track_name,
                    m.track_identity, m.physics_hash, m.server_tick, m.reconnect_token, m.observer, m.track_bytes);
}
auto tie(const jp::SnapshotAck& m) { return std::tie(m.ack_snapshot_tick); }
auto tie(const jp::TrackRequest& m) { return std::tie(m.offset); }
auto tie(const jp::TrackChunk& m) { return std::tie(m.offset, m.bytes); }
auto tie(const jp::Refuse& m) { return std::tie(m.reason, m.code); }
auto tie(const jp::InputBatch& m) { return std::tie(m.first_tick, m.inputs, m.ack_snapshot_tick); }
auto tie(const jp::Snapshot& m) {
    return std::tie(m.server_tick, m.baseline_tick, m.last_applied_input_tick, m.input_margin_ticks, m.phase,
                    m.race_number, m.world);
}
auto tie(const jp::PlayerInfo& m) { return std::tie(m.slot, m.name, m.spectating); }
auto tie(const jp::StandingEntry& m) { return std::tie(m.slot, m.name, m.finished, m.lap, m.finish_time_s); }
auto tie(const jp::Goodbye& m) { return std::tie(m.reason, m.code); }

template <typename T>
bool same_list(const std::vector<T>& a, const std::vector<T>& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (tie(a[i]) != tie(b[i])) return false;
    return true;
}
bool same(const jp::RaceStatus& a, const jp::RaceStatus& b) {
    return std::tie(a.phase, a.race_number, a.start_tick, a.laps) ==
               std::tie(b.phase, b.race_number, b.start_tick, b.laps) &&
           same_list(a.players, b.players);
}
bool same(const jp::Results& a, const jp::Results& b) {
    return a.race_number == b.race_number && a.state_hash == b.state_hash && same_list(a.standings, b.standings);
}
template <typename T>
bool same(const T& a, const T& b) {
    return tie(a) == tie(b);
}
bool same(const jp::Message& a, const jp::Message& b) {
    if (a.index() != b.index()) return false;
    return std::visit([&](const auto& x) { return same(x, std::get<std::decay_t<decltype(x)>>(b)); }, a);
}

/// A real world payload (two empty slots) for `tick`, against a baseline at
/// `base_tick` (kNoTick: none). Snapshot.server_tick is its first field.
std::vector<std::uint8_t> world_payload(std::uint32_t tick, std::uint32_t base_tick) {
    jp::WorldSnapshot now{jetrace::make_world(2, 3, 0), std::vector<jetrace::Input>(2), 120, {}};
    now.state.tick = tick;
    if (base_tick == jp::kNoTick) return jp::encode_world(now, nullptr);
    jp::WorldSnapshot base = now;
    base.state.tick = base_tick;
    return jp::encode_world(now, &base);
}

jp::Snapshot snapshot(std::uint32_t tick, std::uint32_t base, std::uint32_t applied, std::int16_t margin,
                      jp::RacePhase phase, std::uint32_t race) {
    return jp::Snapshot{tick, base, applied, margin, phase, race, world_payload(tick, base)};
}

std::vector<std::uint8_t> token(std::uint8_t first) {
    std::vector<std::uint8_t> t(jp::kTokenBytes);
    for (std::size_t i = 0; i < t.size(); ++i) t[i] = static_cast<std::uint8_t>(first + i * 17);
    return t;
}

/// One of every message, with non-default values and limits.
std::vector<jp::Message> sample_messages() {
    std::vector<jp::Message> out;
    out.push_back(jp::Hello{1, "Ayrton", {}, {}});
    out.push_back(jp::Hello{7, "\xc3\xa9t\xc3\xa9 \xe2\x9c\x93 1234567890123456789012", token(3), {}});  // 32 bytes
    out.push_back(jp::Hello{0, "", {}, {}});
    out.push_back(jp::Hello{2, "Alain", token(4), std::vector<std::uint8_t>(jp::kMaxConnectTokenBytes, 0x5A)});
    out.push_back(jp::Welcome{1, 5, 8, 120, 60, "ring", 0x1234567890abcdefull, 0xfedcba0987654321ull, 99, token(9), {}});
    out.push_back(jp::Welcome{2, 63, 64, 10000, 1, std::string(256, 't'), 0, 0, 0xFFFFFFFFu, {}, {}});
    out.push_back(jp::Hello{5, "watcher", {}, {}, true});
    out.push_back(jp::Welcome{5, 0, 8, 120, 60, "ring", 1, 2, 3, {}, {}, true});
    out.push_back(jp::Welcome{5, 1, 8, 120, 60, "my.obj", 1, 2, 3, token(2), {}, false, jp::kMaxTrackBytes});
    out.push_back(jp::Refuse{"server full"});
    out.push_back(jp::Refuse{std::string(256, 'r')});
    out.push_back(jp::Refuse{"server full", static_cast<std::uint16_t>(jp::CloseCode::refused_full)});
    out.push_back(jp::Refuse{"from a newer server", 2999});
    jp::InputBatch batch{1000, {}, 998};
    for (int i = 0; i < 64; ++i) batch.inputs.push_back(jetrace::Input::clamped(i % 16, i % 31 - 15, i % 2));
    out.push_back(batch);
    out.push_back(jp::InputBatch{0xFFFFFFFFu, {jetrace::Input::clamped(15, -15, 1)}, jp::kNoTick});
    out.push_back(jp::InputBatch{0, {jetrace::Input::clamped(0, 15, 0)}, 0xFFFFFFFEu});
    out.push_back(jp::InputBatch{0xFFFFFFC0u, std::vector<jetrace::Input>(64, jetrace::Input::clamped(7, 0, 0)), 0});
    jp::InputBatch runs{1234, {}, 1234};
    for (int i = 0; i < 20; ++i) runs.inputs.push_back(jetrace::Input::clamped(15, i / 3 - 3, i / 10));
    out.push_back(runs);
    out.push_back(snapshot(5000, 4996, 5003, -3, jp::RacePhase::racing, 2));
    out.push_back(snapshot(7, jp::kNoTick, jp::kNoTick, 32767, jp::RacePhase::finished, 0));
    out.push_back(snapshot(0xFFFFFFFFu, 0, 0, -32768, jp::RacePhase::lobby, 0xFFFFFFFFu));
    out.push_back(snapshot(0, jp::kNoTick, 0xFFFFFFFEu, -32767, jp::RacePhase::countdown, 1));
    out.push_back(snapshot(0xFFFFFFFFu, 0xFFFFFFFEu, 0xFFFFFFFEu, 0, jp::RacePhase::racing, 70000));
    out.push_back(snapshot(120000, 119998, 119999, 2, jp::RacePhase::racing, 3));
    jp::RaceStatus status{jp::RacePhase::countdown, 3, 12345, 5, {}};
    for (std::uint8_t s = 0; s < 64; ++s) status.players.push_back({static_cast<std::uint8_t>(63 - s), "p", s % 3 == 0});
    out.push_back(status);
    out.push_back(jp::RaceStatus{jp::RacePhase::lobby, 0, 0, 1, {}});
    jp::Results results{4, {}, 0xabcdef0123456789ull};
    results.standings.push_back({2, "winner", true, 3, 61.25});
    results.standings.push_back({0, "second", true, 3, 62.0078125});
    results.standings.push_back({1, "dnf", false, 1, 0.0});
    out.push_back(results);
    out.push_back(jp::Goodbye{"bye"});
    out.push_back(jp::Goodbye{""});
    out.push_back(jp::Goodbye{"no hello within 5 s", static_cast<std::uint16_t>(jp::CloseCode::no_hello)});
    out.push_back(jp::Goodbye{"", 0xFFFF});
    out.push_back(jp::SnapshotAck{});
    out.push_back(jp::SnapshotAck{0});
    out.push_back(jp::SnapshotAck{123456});
    out.push_back(jp::TrackRequest{});
    out.push_back(jp::TrackRequest{0xFFFFFFFFu});
    out.push_back(jp::TrackChunk{0, {0x4A}});
    out.push_back(jp::TrackChunk{jp::kMaxTrackBytes - static_cast<std::uint32_t>(jp::kTrackChunkBytes),
                                 std::vector<std::uint8_t>(jp::kTrackChunkBytes, 0x7E)});
    return out;
}

std::uint64_t test_seed() { return jetrace::test::test_seed(20240521u); }

bool decodes(std::span<const std::uint8_t> bytes, std::string* why = nullptr) {
    jp::Message m;
    std::string error;
    const bool ok = jp::decode(bytes, m, error);
    if (!ok && why) *why = error;
    return ok;
}

/// The file identifier of each message (docs/PROTOCOL.md, "Messages"), in
/// the order of jp::Message's alternatives.
const char* const kIds[] = {"JTR1", "JWLC", "JTR1", "JINP", "JSNP", "JRST", "JRES", "JBYE", "JACK", "JTRQ", "JTRC"};

using jetrace::test::Bits;
using jetrace::test::envelope;
using jetrace::test::finish;
using jetrace::test::input_batch;
using jetrace::test::snapshot_message;

}  // namespace

// ================================================================ messages

TEST(ProtoMessages, EveryMessageRoundTrips) {
    for (const jp::Message& m : sample_messages()) {
        const std::vector<std::uint8_t> bytes = jp::encode(m);
        ASSERT_LE(bytes.size(), jp::kMaxMessageBytes);
        jp::Message back;
        std::string error;
        ASSERT_TRUE(jp::decode(bytes, back, error)) << "message " << m.index() << ": " << error;
        EXPECT_TRUE(same(m, back)) << "message " << m.index();
    }
}

TEST(ProtoMessages, DecodesFromUnalignedMemory) {
    for (const jp::Message& m : sample_messages()) {
        const std::vector<std::uint8_t> bytes = jp::encode(m);
        std::vector<std::uint8_t> shifted(bytes.size() + 1);
        std::copy(bytes.begin(), bytes.end(), shifted.begin() + 1);
        jp::Message back;
        std::string error;
        ASSERT_TRUE(jp::decode(std::span(shifted).subspan(1), back, error)) << error;
        EXPECT_TRUE(same(m, back));
    }
}

TEST(ProtoMessages, RejectsEmptyOversizedAndWrongIdentifier) {
    std::string why;
    EXPECT_FALSE(decodes({}, &why));
    EXPECT_NE(why.find("empty"), std::string::npos);
    std::vector<std::uint8_t> big = jp::encode(jp::Goodbye{"x"});
    big.resize(jp::kMaxMessageBytes + 1);
    EXPECT_FALSE(decodes(big, &why));
    std::vector<std::uint8_t> bytes = jp::encode(jp::Hello{1, "a", {}, {}});
    bytes[4] = 'X';
    EXPECT_FALSE(decodes(bytes, &why));
    EXPECT_NE(why.find("identifier"), std::string::npos) << why;
}

TEST(ProtoMessages, RejectsEveryTruncation) {
    for (const jp::Message& m : sample_messages()) {
        const std::vector<std::uint8_t> bytes = jp::encode(m);
        // decode() reads a Snapshot's world payload only up to its tick:
        // decode_world rejects a cut world (ProtoWorld tests).
        std::size_t checked = bytes.size();
        if (std::holds_alternative<jp::Snapshot>(m)) checked = 8 + 4 + 1;
        for (std::size_t len = 0; len < checked; ++len)
            EXPECT_FALSE(decodes(std::span(bytes).first(len))) << "message " << m.index() << " cut to " << len;
    }
}

TEST(ProtoMessages, RandomBytesNeverCrash) {
    std::mt19937_64 rng(test_seed());
    const auto samples = sample_messages();
    int accepted = 0;
    for (int i = 0; i < 10000; ++i) {
        std::vector<std::uint8_t> buf;
        if (i % 3 == 0) {
            // Pure noise, often with the right identifier to reach the verifier.
            buf.resize(1 + rng() % 300);
            for (auto& b : buf) b = static_cast<std::uint8_t>(rng());
            if (buf.size() >= 8 && (rng() & 1)) std::copy_n(kIds[rng() % std::size(kIds)], 4, buf.begin() + 4);
        } else {
            // A valid message with a few bytes changed.
            buf = jp::encode(samples[rng() % samples.size()]);
            const int flips = 1 + static_cast<int>(rng() % 4);
            for (int f = 0; f < flips; ++f) buf[rng() % buf.size()] = static_cast<std::uint8_t>(rng());
        }
        jp::Message m;
        std::string error;
        if (!jp::decode(buf, m, error)) continue;
        ++accepted;
        // Whatever decodes is in range: it encodes (encode asserts the same
        // rules) and decodes to the same message.
        jp::Message again;
        EXPECT_TRUE(jp::decode(jp::encode(m), again, error)) << error;
        EXPECT_TRUE(same(m, again)) << "iteration " << i;
    }
    std::cout << "[ info ] mutated/random messages accepted: " << accepted << " of 10000\n";
}

TEST(ProtoMessages, RejectsOutOfRangeFields) {
    std::string why;
    auto rejects = [&](const std::vector<std::uint8_t>& bytes, const char* field) {
        const bool ok = decodes(bytes, &why);
        EXPECT_FALSE(ok) << field;
        EXPECT_NE(why.find(field), std::string::npos) << "error '" << why << "' does not name " << field;
    };
    auto hello = [](const std::string& name, std::vector<std::uint8_t> tok) {
        fb::FlatBufferBuilder b;
        auto n = b.CreateString(name);
        auto t = b.CreateVector(tok);
        return envelope(b, w::Handshake_Hello, w::CreateHello(b, 1, n, t).Union());
    };
    rejects(hello(std::string(33, 'n'), {}), "Hello.name");
    rejects(hello("bad\x01", {}), "Hello.name");
    rejects(hello("bad\xff", {}), "Hello.name");
    rejects(hello("\xc0\xaf", {}), "Hello.name");  // overlong '/'
    rejects(hello("ok", std::vector<std::uint8_t>(5, 1)), "Hello.reconnect_token");
    EXPECT_TRUE(decodes(hello("ok", {})));
    {  // Hello without its required name
        fb::FlatBufferBuilder b;
        const auto start = b.StartTable();
        b.AddElement<std::uint16_t>(w::Hello::VT_PROTOCOL_VERSION, 1, 0);
        EXPECT_FALSE(decodes(envelope(b, w::Handshake_Hello, fb::Offset<void>(b.EndTable(start))), &why));
    }
    {  // InputBatch and Snapshot without their payload, or not starting with 4 zero bytes
        EXPECT_FALSE(decodes(input_batch({}), &why));
        EXPECT_NE(why.find("InputBatch.payload: missing"), std::string::npos) << why;
        EXPECT_FALSE(decodes(snapshot_message({}), &why));
        EXPECT_NE(why.find("Snapshot.payload: missing"), std::string::npos) << why;
        std::vector<std::uint8_t> bytes = jp::encode(jp::InputBatch{7, {jetrace::Input{}}, jp::kNoTick});
        ASSERT_TRUE(decodes(bytes));
        bytes[2] = 1;
        EXPECT_FALSE(decodes(bytes, &why));
        EXPECT_NE(why.find("4 zero bytes"), std::string::npos) << why;
    }
    {  // a Snapshot payload too long to re-encode within kMaxMessageBytes
        const std::vector<std::uint8_t> big(jp::kMaxSnapshotPayloadBytes + 1, 0);
        const auto bytes = snapshot_message(big);
        ASSERT_LE(bytes.size(), jp::kMaxMessageBytes);
        EXPECT_FALSE(decodes(bytes, &why));
        EXPECT_NE(why.find("Snapshot.payload: too long"), std::string::npos) << why;
    }
    auto welcome = [](std::uint8_t slot, std::uint8_t max, std::uint16_t rate, std::uint16_t snap) {
        fb::FlatBufferBuilder b;
        auto name = b.CreateString("ring");
        return finish(b, w::CreateWelcome(b, 1, slot, max, rate, snap, name, 0, 0, 0, 0), "JWLC");
    };
    rejects(welcome(64, 64, 120, 60), "Welcome.slot");
    rejects(welcome(0, 65, 120, 60), "Welcome.max_players");
    rejects(welcome(0, 0, 120, 60), "Welcome.max_players");
    rejects(welcome(0, 8, 0, 60), "Welcome.tick_rate_hz");
    rejects(welcome(0, 8, 120, 10001), "Welcome.snapshot_rate_hz");
    {  // protocol version 5's fields: bools stored as 0 or 1, a bounded track size
        fb::FlatBufferBuilder b;
        auto name = b.CreateString("ring");
        rejects(finish(b, w::CreateWelcome(b, 5, 0, 8, 120, 60, name, 0, 0, 0, 0, 0, false, jp::kMaxTrackBytes + 1), "JWLC"),
                "Welcome.track_bytes");
        fb::FlatBufferBuilder b2;
        auto name2 = b2.CreateString("ring");
        const auto start = b2.StartTable();
        b2.AddOffset(w::Welcome::VT_TRACK_NAME, name2);
        b2.AddElement<std::uint8_t>(w::Welcome::VT_MAX_PLAYERS, 8, 0);
        b2.AddElement<std::uint8_t>(w::Welcome::VT_OBSERVER, 2, 0);
        rejects(finish(b2, fb::Offset<w::Welcome>(b2.EndTable(start)), "JWLC"), "Welcome.observer");
        fb::FlatBufferBuilder b3;
        auto n3 = b3.CreateString("x");
        const auto h = b3.StartTable();
        b3.AddOffset(w::Hello::VT_NAME, n3);
        b3.AddElement<std::uint8_t>(w::Hello::VT_OBSERVE, 7, 0);
        rejects(envelope(b3, w::Handshake_Hello, fb::Offset<void>(b3.EndTable(h))), "Hello.observe");
    }
    auto chunk = [](std::uint32_t offset, std::size_t n, bool with_bytes = true) {
        fb::FlatBufferBuilder b;
        const auto bytes = b.CreateVector(std::vector<std::uint8_t>(n, 1));
        const auto start = b.StartTable();
        b.AddElement<std::uint32_t>(w::TrackChunk::VT_OFFSET, offset, 0);
        if (with_bytes) b.AddOffset(w::TrackChunk::VT_BYTES, bytes);
        return finish(b, fb::Offset<w::TrackChunk>(b.EndTable(start)), "JTRC");
    };
    rejects(chunk(0, 0), "TrackChunk.bytes");
    rejects(chunk(0, jp::kTrackChunkBytes + 1), "TrackChunk.bytes");
    rejects(chunk(0, 1, false), "message");  // required: the verifier refuses it
    rejects(chunk(jp::kMaxTrackBytes, 1), "TrackChunk.offset");
    rejects(chunk(0xFFFFFFFFu, 1), "TrackChunk.offset");
    EXPECT_TRUE(decodes(chunk(jp::kMaxTrackBytes - 1, 1)));
    auto status = [](std::vector<std::uint8_t> slots, std::uint8_t spectating = 0) {
        fb::FlatBufferBuilder b;
        std::vector<fb::Offset<w::PlayerInfo>> players;
        for (std::uint8_t s : slots) {
            auto name = b.CreateString("p");
            const auto start = b.StartTable();
            b.AddOffset(w::PlayerInfo::VT_NAME, name);
            b.AddElement<std::uint8_t>(w::PlayerInfo::VT_SLOT, s, 0);
            b.AddElement<std::uint8_t>(w::PlayerInfo::VT_SPECTATING, spectating, 0);
            players.push_back(fb::Offset<w::PlayerInfo>(b.EndTable(start)));
        }
        auto list = b.CreateVector(players);
        return finish(b, w::CreateRaceStatus(b, w::RacePhase_Racing, 1, 0, 3, list), "JRST");
    };
    rejects(status({0, 64}), "RaceStatus.players[1].slot");
    rejects(status({3, 3}), "RaceStatus.players[1].slot");
    rejects(status({1}, 2), "RaceStatus.players[0].spectating");
    std::vector<std::uint8_t> many(65);
    for (std::size_t i = 0; i < many.size(); ++i) many[i] = static_cast<std::uint8_t>(i);
    rejects(status(many), "RaceStatus.players");
    auto results = [](double time) {
        fb::FlatBufferBuilder b;
        auto e = w::CreateStandingEntry(b, 0, b.CreateString("x"), true, 1, time);
        auto list = b.CreateVector(std::vector<fb::Offset<w::StandingEntry>>{e});
        return finish(b, w::CreateResults(b, 1, list, 0), "JRES");
    };
    rejects(results(std::numeric_limits<double>::quiet_NaN()), "finish_time_s");
    rejects(results(std::numeric_limits<double>::infinity()), "finish_time_s");
    rejects(results(-1.0), "finish_time_s");
    EXPECT_TRUE(decodes(results(12.5)));
    {  // a message under another message's identifier
        fb::FlatBufferBuilder b;
        auto r = w::CreateGoodbye(b, b.CreateString("x"));
        EXPECT_FALSE(decodes(finish(b, r, "JRES"), &why));
    }
    {  // an Envelope holds only Hello or Refuse
        fb::FlatBufferBuilder b;
        auto r = w::CreateGoodbye(b, b.CreateString("x"));
        rejects(envelope(b, static_cast<w::Handshake>(2), r.Union()), "Envelope.body_type");
        fb::FlatBufferBuilder b2;
        auto r2 = w::CreateRefuse(b2, b2.CreateString("x"));
        rejects(envelope(b2, w::Handshake_NONE, r2.Union()), "Envelope.body_type");
    }
    {  // Welcome's table under Welcome's identifier but with the builder's padding: accepted
        fb::FlatBufferBuilder b;
        auto name = b.CreateString("ring");
        EXPECT_TRUE(decodes(finish(b, w::CreateWelcome(b, 2, 0, 8, 120, 60, name, 0, 0, 0, 0), "JWLC")));
    }
    {  // a long reason
        fb::FlatBufferBuilder b;
        auto r = w::CreateRefuse(b, b.CreateString(std::string(257, 'x')));
        rejects(envelope(b, w::Handshake_Refuse, r.Union()), "Refuse.reason");
    }
}

TEST(ProtoMessages, HelloAndRefuseAreThoseOfVersion1) {
    // Bytes protocol version 1 produced: every version reads the other's
    // Hello, and a server answers a version mismatch with a Refuse the
    // client can read.
    const std::vector<std::uint8_t> hello_v1 = {
        0x10, 0x00, 0x00, 0x00, 0x4a, 0x54, 0x52, 0x31, 0x08, 0x00, 0x0c, 0x00, 0x07, 0x00, 0x08, 0x00, 0x08, 0x00, 0x00,
        0x00, 0x00, 0x00, 0x00, 0x01, 0x0c, 0x00, 0x00, 0x00, 0x08, 0x00, 0x0c, 0x00, 0x06, 0x00, 0x08, 0x00, 0x08, 0x00,
        0x00, 0x00, 0x00, 0x00, 0x01, 0x00, 0x04, 0x00, 0x00, 0x00, 0x06, 0x00, 0x00, 0x00, 0x41, 0x79, 0x72, 0x74, 0x6f,
        0x6e, 0x00, 0x00};
    const std::vector<std::uint8_t> refuse_v1 = {
        0x10, 0x00, 0x00, 0x00, 0x4a, 0x54, 0x52, 0x31, 0x08, 0x00, 0x0e, 0x00, 0x07, 0x00, 0x08, 0x00, 0x08, 0x00, 0x00,
        0x00, 0x00, 0x00, 0x00, 0x03, 0x0c, 0x00, 0x00, 0x00, 0x00, 0x00, 0x06, 0x00, 0x08, 0x00, 0x04, 0x00, 0x06, 0x00,
        0x00, 0x00, 0x04, 0x00, 0x00, 0x00, 0x32, 0x00, 0x00, 0x00, 0x70, 0x72, 0x6f, 0x74, 0x6f, 0x63, 0x6f, 0x6c, 0x20,
        0x76, 0x65, 0x72, 0x73, 0x69, 0x6f, 0x6e, 0x20, 0x32, 0x20, 0x6e, 0x6f, 0x74, 0x20, 0x73, 0x75, 0x70, 0x70, 0x6f,
        0x72, 0x74, 0x65, 0x64, 0x20, 0x28, 0x73, 0x65, 0x72, 0x76, 0x65, 0x72, 0x20, 0x73, 0x70, 0x65, 0x61, 0x6b, 0x73,
        0x20, 0x31, 0x29, 0x00, 0x00};
    const jp::Hello hello{1, "Ayrton", {}, {}};
    const jp::Refuse refuse{"protocol version 2 not supported (server speaks 1)"};
    EXPECT_EQ(jp::encode(hello), hello_v1);
    EXPECT_EQ(jp::encode(refuse), refuse_v1);
    jp::Message m;
    std::string error;
    ASSERT_TRUE(jp::decode(hello_v1, m, error)) << error;
    EXPECT_TRUE(same(m, jp::Message{hello}));
    ASSERT_TRUE(jp::decode(refuse_v1, m, error)) << error;
    EXPECT_TRUE(same(m, jp::Message{refuse}));
}

TEST(ProtoMessages, RejectsBadInputBatchPayloads) {
    std::string why;
    auto rejects = [&](const Bits& payload, const char* field, std::uint8_t padding = 0) {
        EXPECT_FALSE(decodes(input_batch(payload.bytes(padding)), &why)) << field;
        EXPECT_NE(why.find(field), std::string::npos) << "error '" << why << "' does not name " << field;
    };
    // first_tick ue(14), count - 1 u(6), ack: 1 bit + se(0) of first_tick - ack,
    // then u(10), and per further input 1 bit "same" or 0 + u(10).
    const std::uint16_t in = jetrace::Input::clamped(15, 15, 1).pack();
    const Bits ok = Bits{}.ue(5, 14).u(1, 6).u(1, 1).se(0, 0).u(in, 10).u(0, 1).u(3, 10);
    ASSERT_TRUE(decodes(input_batch(ok.bytes()), &why)) << why;
    jp::Message m;
    ASSERT_TRUE(jp::decode(input_batch(ok.bytes()), m, why));
    EXPECT_TRUE(same(m, jp::Message{jp::InputBatch{5, {jetrace::Input::unpack(in), jetrace::Input::unpack(3)}, 5}}));
    EXPECT_TRUE(decodes(input_batch(Bits{}.ue(5, 14).u(2, 6).u(0, 1).u(in, 10).u(1, 1).u(1, 1).bytes())));
    rejects(Bits{}.ue(0x100000000ull, 14).u(0, 6).u(0, 1).u(in, 10), "InputBatch.first_tick");
    rejects(Bits{}.ue(0xFFFFFFFFu, 14).u(1, 6).u(0, 1).u(in, 10).u(1, 1), "InputBatch.first_tick");  // overflows
    rejects(Bits{}.ue(5, 14).u(0, 6).u(1, 1).se(6, 0).u(in, 10), "InputBatch.ack_snapshot_tick");  // tick -1
    rejects(Bits{}.ue(5, 14).u(0, 6).u(1, 1).se(5 - 0xFFFFFFFFll, 0).u(in, 10), "InputBatch.ack_snapshot_tick");
    rejects(Bits{}.ue(5, 14).u(0, 6).u(0, 1).u(0x1F0, 10), "InputBatch.inputs");  // steer bits 31
    rejects(Bits{}.ue(5, 14).u(2, 6).u(0, 1).u(in, 10).u(1, 1), "InputBatch.inputs");  // one input short
    rejects(Bits{}.ue(5, 14).u(0, 6).u(0, 1).u(in, 10).u(0, 8), "InputBatch.payload");  // trailing byte
    rejects(Bits{}.ue(5, 14).u(1, 6).u(0, 1).u(in, 10).u(1, 1), "InputBatch.payload", 1);  // padding bit set
    rejects(Bits{}, "InputBatch.payload: missing");  // empty
}

TEST(ProtoMessages, RejectsBadSnapshotPayloads) {
    std::string why;
    auto rejects = [&](const Bits& header, const std::vector<std::uint8_t>& world, const char* field,
                       std::uint8_t padding = 0) {
        std::vector<std::uint8_t> payload = header.bytes(padding);
        payload.insert(payload.end(), world.begin(), world.end());
        EXPECT_FALSE(decodes(snapshot_message(payload), &why)) << field;
        EXPECT_NE(why.find(field), std::string::npos) << "error '" << why << "' does not name " << field;
    };
    // phase u(2), baseline 1 bit + ue(14), last applied 1 bit + se(0) of
    // server_tick - 1 - tick, margin ue(3), race_number ue(2); zero padding
    // to a byte; the world payload, whose first field gives server_tick.
    const auto world = world_payload(100, 98);
    const auto fresh = world_payload(100, jp::kNoTick);
    auto header = [](std::uint64_t phase, std::uint64_t base, std::int64_t applied, std::uint64_t margin) {
        return Bits{}.u(phase, 2).u(1, 1).ue(base, 14).u(1, 1).se(applied, 0).ue(margin, 3).ue(4, 2);
    };
    for (std::uint64_t phase = 0; phase < 4; ++phase) {
        std::vector<std::uint8_t> payload = header(phase, 98, 0, 0).bytes();
        payload.insert(payload.end(), world.begin(), world.end());
        jp::Message m;
        ASSERT_TRUE(jp::decode(snapshot_message(payload), m, why)) << why;
        EXPECT_TRUE(same(m, jp::Message{jp::Snapshot{100, 98, 99, -32768, static_cast<jp::RacePhase>(phase), 4, world}}));
    }
    {  // margin: 0 is -32768, else zigzag + 1
        std::vector<std::uint8_t> payload = header(2, 98, 0, 6).bytes();
        payload.insert(payload.end(), world.begin(), world.end());
        jp::Message m;
        ASSERT_TRUE(jp::decode(snapshot_message(payload), m, why)) << why;
        EXPECT_EQ(std::get<jp::Snapshot>(m).input_margin_ticks, -3);
    }
    rejects(header(2, 0xFFFFFFFFu, 0, 1), world, "Snapshot.baseline_tick");  // kNoTick is "none"
    rejects(header(2, 0x100000000ull, 0, 1), world, "Snapshot.baseline_tick");
    rejects(header(2, 98, 100, 1), world, "Snapshot.last_applied_input_tick");  // tick -1
    rejects(header(2, 98, 100 - 0x100000000ll, 1), world, "Snapshot.last_applied_input_tick");  // kNoTick
    rejects(header(2, 98, 0, 65536), world, "Snapshot.input_margin_ticks");
    rejects(Bits{}.u(2, 2).u(0, 1).u(0, 1).ue(1, 3).ue(0x100000000ull, 2), fresh, "Snapshot.race_number");
    rejects(header(2, 98, 0, 1), world, "Snapshot.payload", 1);  // padding bit set
    rejects(header(2, 98, 0, 1), {}, "Snapshot.world");  // no world
    rejects(Bits{}.u(2, 2).u(0, 1).u(0, 1).ue(1, 3).ue(1, 2), {0, 0, 1}, "Snapshot.world");  // 24-bit tick
    rejects(header(2, 0xFFFFFFFEu, 0, 1), world, "Snapshot.world");  // tick past 2^32 - 1
    rejects(Bits{}, {}, "Snapshot.payload: missing");  // empty
}

TEST(ProtoMessages, IdentifiersAndSizes) {
    const auto samples = sample_messages();
    for (const jp::Message& m : samples) {
        const auto bytes = jp::encode(m);
        EXPECT_EQ(std::string(bytes.begin() + 4, bytes.begin() + 8), kIds[m.index()]) << "message " << m.index();
    }
    // The two frequent messages: 8 bytes (4 zero bytes, the identifier),
    // then the packed payload.
    jp::Snapshot s{5000, 4998, 4999, 3, jp::RacePhase::racing, 1, std::vector<std::uint8_t>(60, 0x5A)};
    s.world[0] = 0xC0;  // ue(2) of 2: server_tick = baseline_tick + 2
    const std::size_t snapshot = jp::encode(s).size();
    EXPECT_EQ(snapshot, 8u + 4u + 60u);  // header: 2 + 16 + 2 + 4 + 3 bits
    std::cout << "[ info ] Snapshot with a 60-byte world: " << snapshot << " bytes\n";
    RecordProperty("snapshot_bytes_world60", std::to_string(snapshot));
    for (std::size_t n : {1u, 6u, 20u}) {
        jp::InputBatch same_inputs{5010, std::vector<jetrace::Input>(n, jetrace::Input::clamped(15, 3, 0)), 5010};
        jp::InputBatch varied = same_inputs;
        for (std::size_t i = 0; i < n; ++i) varied.inputs[i] = jetrace::Input::clamped(15, static_cast<int>(i * 7 % 31) - 15, 0);
        const std::size_t a = jp::encode(same_inputs).size(), b = jp::encode(varied).size();
        // 15 + 6 + 2 bits, 10 bits for the first input, 1 or 11 per other.
        EXPECT_EQ(a, 8u + (23 + 10 + (n - 1) + 7) / 8);
        EXPECT_EQ(b, 8u + (23 + 10 + 11 * (n - 1) + 7) / 8);
        std::cout << "[ info ] InputBatch with " << n << " inputs: " << a << " bytes (all equal), " << b
                  << " (all different)\n";
        RecordProperty("input_batch_bytes_" + std::to_string(n), std::to_string(a) + "/" + std::to_string(b));
    }
}

TEST(ProtoMessages, RandomPayloadsNeverCrash) {
    // Random bits inside valid InputBatch and Snapshot tables reach the
    // payload decoders; whatever decodes encodes to the same message.
    std::mt19937_64 rng(test_seed() + 1);
    int accepted[2] = {0, 0};
    for (int i = 0; i < 10000; ++i) {
        std::vector<std::uint8_t> payload(1 + rng() % 24);
        for (auto& b : payload) b = static_cast<std::uint8_t>(rng() & rng());  // mostly zero bits: short codes
        const bool snap = (i & 1) != 0;
        jp::Message m;
        std::string error;
        if (!jp::decode(snap ? snapshot_message(payload) : input_batch(payload), m, error)) {
            EXPECT_FALSE(error.empty());
            continue;
        }
        ++accepted[snap ? 1 : 0];
        jp::Message again;
        EXPECT_TRUE(jp::decode(jp::encode(m), again, error)) << error;
        EXPECT_TRUE(same(m, again)) << "iteration " << i;
    }
    std::cout << "[ info ] random payloads accepted: " << accepted[0] << " InputBatch, " << accepted[1]
              << " Snapshot of 5000 each\n";
}

TEST(ProtoMessages, PhysicsHashCoversEveryField) {
    // A new field in PhysicsSettings changes its size: add it to the hash
    // (jetrace::physics_fingerprint, which jp::physics_hash is) and below.
    EXPECT_EQ(sizeof(jetrace::PhysicsSettings), 136u) << "PhysicsSettings changed: update the physics hash";
    const jetrace::PhysicsSettings base;
    const std::uint64_t h = jp::physics_hash(base);
    EXPECT_EQ(h, jp::physics_hash(jetrace::PhysicsSettings{}));
    using S = jetrace::PhysicsSettings;
    const std::vector<void (*)(S&)> mutations = {
        [](S& s) { s.tick_rate_hz = 60; }, [](S& s) { s.gravity_mps2 = std::nextafter(s.gravity_mps2, 10.0); },
        [](S& s) { s.car_radius_m = 2.0; }, [](S& s) { s.thrust_mps2 = 20.0; },
        [](S& s) { s.drag_per_m = 1e-4; }, [](S& s) { s.brake_mps2 = 20.0; },
        [](S& s) { s.steer_rate_radps = 1.0; }, [](S& s) { s.grip_mps2 = 30.0; },
        [](S& s) { s.slide_mps2 = 10.0; }, [](S& s) { s.align_rate_per_s = 10.0; },
        [](S& s) { s.ride_min_cos = 0.4; }, [](S& s) { s.no_progress_s = 5.0; },
        [](S& s) { s.resolver_passes = 10; }, [](S& s) { s.resolver_epsilon_m = 1e-3; },
        [](S& s) { s.contact_skin_m = 0.1; }, [](S& s) { s.integrator = jetrace::Integrator::explicit_euler; },
        [](S& s) { s.quantize_state = false; }, [](S& s) { s.collision_mode = jetrace::CollisionMode::discrete; },
        [](S& s) { s.sweep_contacts = 2; }, [](S& s) { s.push_out = jetrace::PushOut::first_contact; }};
    for (std::size_t i = 0; i < mutations.size(); ++i) {
        S s = base;
        mutations[i](s);
        EXPECT_NE(jp::physics_hash(s), h) << "field " << i;
    }
}

TEST(ProtoMessages, PhaseNames) {
    EXPECT_STREQ(jp::to_string(jp::RacePhase::lobby), "lobby");
    EXPECT_STREQ(jp::to_string(jp::RacePhase::countdown), "countdown");
    EXPECT_STREQ(jp::to_string(jp::RacePhase::racing), "racing");
    EXPECT_STREQ(jp::to_string(jp::RacePhase::finished), "finished");
}

// Close codes: every code has its name and falls in its range; a code this
// build does not know still falls in a range (a newer peer's).
TEST(CloseCodes, NamesAndRanges) {
    using jp::CloseClass;
    using jp::CloseCode;
    const auto u = [](CloseCode c) { return static_cast<std::uint16_t>(c); };
    EXPECT_EQ(jp::close_class(u(CloseCode::unspecified)), CloseClass::unspecified);
    for (CloseCode c : {CloseCode::left, CloseCode::server_shutdown, CloseCode::replaced, CloseCode::lobby_cancelled})
        EXPECT_EQ(jp::close_class(u(c)), CloseClass::normal) << u(c);
    for (CloseCode c : {CloseCode::refused_version, CloseCode::refused_token, CloseCode::refused_clock,
                        CloseCode::refused_full, CloseCode::refused_reconnect, CloseCode::refused_draining,
                        CloseCode::refused_unallocated, CloseCode::refused_observers_full,
                        CloseCode::refused_pre_hello_cap})
        EXPECT_EQ(jp::close_class(u(c)), CloseClass::refused) << u(c);
    for (CloseCode c : {CloseCode::no_hello, CloseCode::malformed, CloseCode::protocol_violation})
        EXPECT_EQ(jp::close_class(u(c)), CloseClass::remote_fault) << u(c);
    EXPECT_EQ(jp::close_code_name(u(CloseCode::refused_full)), "refused_full");
    EXPECT_EQ(u(CloseCode::refused_pre_hello_cap), 2008);
    EXPECT_EQ(jp::close_code_name(2008), "refused_pre_hello_cap");
    EXPECT_EQ(jp::close_code_name(2999), "");
    EXPECT_EQ(jp::close_class(2999), CloseClass::refused);
    EXPECT_EQ(jp::close_class(7000), CloseClass::other);
}
