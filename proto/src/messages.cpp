// Messages <-> flatbuffers (schema: proto/jetrace.fbs). The rules decode()
// enforces are listed in docs/PROTOCOL.md, sections "Messages" and
// "Validation"; encode() asserts the same rules, so whatever it produces
// decodes. InputBatch and Snapshot, the two messages sent many times a
// second, are no flatbuffers: 8 bytes (4 zero bytes, the identifier) and a
// bit-packed payload (packed_message()).
#include "jetrace/proto/messages.hpp"

#include "jetrace_generated.h"
#include "packed_payloads.hpp"
#include "physics_wire.hpp"

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <type_traits>

namespace jetrace::proto {

namespace {

namespace fb = flatbuffers;
namespace w = jetrace::wire;

/// Longest track name in Welcome (unit: bytes of UTF-8).
constexpr std::size_t kMaxTrackNameBytes = 256;
constexpr int kMaxRateHz = 10000;

/// The root table and file identifier of each message but Hello and Refuse
/// (the `id` attributes in jetrace.fbs).
template <typename M>
struct Wire;
// clang-format off
template <> struct Wire<Welcome> { using Table = w::Welcome; static constexpr const char* kId = "JWLC"; };
template <> struct Wire<InputBatch> { using Table = w::InputBatch; static constexpr const char* kId = "JINP"; };
template <> struct Wire<Snapshot> { using Table = w::Snapshot; static constexpr const char* kId = "JSNP"; };
template <> struct Wire<RaceStatus> { using Table = w::RaceStatus; static constexpr const char* kId = "JRST"; };
template <> struct Wire<Results> { using Table = w::Results; static constexpr const char* kId = "JRES"; };
template <> struct Wire<Goodbye> { using Table = w::Goodbye; static constexpr const char* kId = "JBYE"; };
template <> struct Wire<SnapshotAck> { using Table = w::SnapshotAck; static constexpr const char* kId = "JACK"; };
template <> struct Wire<TrackRequest> { using Table = w::TrackRequest; static constexpr const char* kId = "JTRQ"; };
template <> struct Wire<TrackChunk> { using Table = w::TrackChunk; static constexpr const char* kId = "JTRC"; };
// clang-format on

/// flatbuffers::Verifier over the whole buffer as root table T with file
/// identifier `id`: every offset, vector, string and table inside it,
/// alignment checked, depth and table count bounded.
template <typename T>
bool verifies(const std::uint8_t* data, std::size_t size, const char* id) {
    fb::Verifier::Options opts;
    opts.max_depth = 8;
    opts.max_tables = 256;
    opts.check_alignment = true;
    fb::Verifier verifier(data, size, opts);
    return verifier.VerifyBuffer<T>(id);
}

/// Valid UTF-8 (no overlong forms, surrogates or code points above
/// U+10FFFF) without control characters (C0, DEL, C1).
bool clean_utf8(std::string_view s) {
    std::size_t i = 0;
    while (i < s.size()) {
        const auto c = static_cast<unsigned char>(s[i]);
        std::uint32_t cp = 0;
        int more = 0;
        if (c < 0x80) {
            cp = c;
        } else if (c >= 0xC2 && c <= 0xDF) {
            cp = c & 0x1Fu;
            more = 1;
        } else if (c >= 0xE0 && c <= 0xEF) {
            cp = c & 0x0Fu;
            more = 2;
        } else if (c >= 0xF0 && c <= 0xF4) {
            cp = c & 0x07u;
            more = 3;
        } else {
            return false;
        }
        if (s.size() - i - 1 < static_cast<std::size_t>(more)) return false;
        for (int k = 1; k <= more; ++k) {
            const auto cc = static_cast<unsigned char>(s[i + static_cast<std::size_t>(k)]);
            if ((cc & 0xC0u) != 0x80u) return false;
            cp = (cp << 6) | (cc & 0x3Fu);
        }
        if ((more == 2 && cp < 0x800) || (more == 3 && (cp < 0x10000 || cp > 0x10FFFF))) return false;  // overlong
        if (cp >= 0xD800 && cp <= 0xDFFF) return false;  // surrogate
        if (cp < 0x20 || (cp >= 0x7F && cp <= 0x9F)) return false;  // control
        i += 1 + static_cast<std::size_t>(more);
    }
    return true;
}

/// Collects the first error and names its field.
class Check {
public:
    explicit Check(std::string& error) : error_(error) {}
    std::string& error() { return error_; }
    bool fail(const std::string& field, const char* what) {
        error_ = field + ": " + what;
        return false;
    }
    /// A required string: at most `max` bytes of clean UTF-8.
    bool text(const fb::String* s, std::size_t max, const std::string& field, std::string& out) {
        if (!s) return fail(field, "missing");
        if (s->size() > max) return fail(field, "too long");
        const std::string_view v(s->c_str(), s->size());
        if (!clean_utf8(v)) return fail(field, "not UTF-8 text (bad encoding or control characters)");
        out.assign(v);
        return true;
    }
    /// An optional token: absent/empty or exactly kTokenBytes.
    bool token(const fb::Vector<std::uint8_t>* t, const std::string& field, std::vector<std::uint8_t>& out) {
        out.clear();
        if (!t || t->size() == 0) return true;
        if (t->size() != kTokenBytes) return fail(field, "must be empty or kTokenBytes long");
        out.assign(t->begin(), t->end());
        return true;
    }
    bool phase(w::RacePhase p, const std::string& field, RacePhase& out) {
        if (static_cast<unsigned>(p) > static_cast<unsigned>(w::RacePhase_MAX)) return fail(field, "unknown phase");
        out = static_cast<RacePhase>(p);
        return true;
    }
    /// A bool field stored as one byte: only 0 or 1.
    template <typename T>
    bool flag(const T* t, fb::voffset_t vt, const std::string& field, bool& out) {
        // Generated tables inherit flatbuffers::Table privately; they are one.
        const auto raw = reinterpret_cast<const fb::Table*>(t)->GetField<std::uint8_t>(vt, 0);
        if (raw > 1) return fail(field, "not a bool");
        out = raw != 0;
        return true;
    }
    /// A slot index below kMaxSlots, not seen before in this list.
    bool slot(std::uint8_t s, std::uint64_t& seen, const std::string& field) {
        if (s >= kMaxSlots) return fail(field, "out of range");
        const std::uint64_t bit = std::uint64_t{1} << s;
        if (seen & bit) return fail(field, "listed twice");
        seen |= bit;
        return true;
    }

private:
    std::string& error_;
};

// ---------------------------------------------------------------- encode

void assert_text(const std::string& s, std::size_t max) {
    assert(s.size() <= max && clean_utf8(s) && "encode: text too long or not clean UTF-8");
    (void)s;
    (void)max;
}

fb::Offset<fb::Vector<std::uint8_t>> token(fb::FlatBufferBuilder& b, const std::vector<std::uint8_t>& t) {
    assert((t.empty() || t.size() == kTokenBytes) && "encode: bad token length");
    return t.empty() ? 0 : b.CreateVector(t);
}

/// Finishes the buffer with the message's identifier, without the
/// builder's trailing alignment padding: the shortest prefix that still
/// verifies (the same offsets, so the same alignment). Verification only
/// grows more lenient with size, so every shorter prefix fails it: a
/// truncated message never decodes.
template <typename M>
std::vector<std::uint8_t> finish(fb::FlatBufferBuilder& b, fb::Offset<typename Wire<M>::Table> root) {
    using T = typename Wire<M>::Table;
    b.Finish(root, Wire<M>::kId);
    const std::uint8_t* p = b.GetBufferPointer();
    std::size_t size = b.GetSize();
    assert(verifies<T>(p, size, Wire<M>::kId) && "encode: the builder's buffer does not verify");
    while (size > 0 && verifies<T>(p, size - 1, Wire<M>::kId)) --size;
    assert(size <= kMaxMessageBytes && "encode: message too large");
    return {p, p + size};
}

/// InputBatch and Snapshot, sent tens of times a second, are no flatbuffer:
/// 4 zero bytes (never a flatbuffer's root offset), the identifier, then the
/// bit-packed payload.
constexpr std::size_t kPackedHeaderBytes = 8;

template <typename M>
std::vector<std::uint8_t> packed_message(const std::vector<std::uint8_t>& payload) {
    std::vector<std::uint8_t> out(kPackedHeaderBytes + payload.size(), 0);
    std::memcpy(out.data() + sizeof(fb::uoffset_t), Wire<M>::kId, fb::kFileIdentifierLength);
    std::copy(payload.begin(), payload.end(), out.begin() + kPackedHeaderBytes);
    assert(out.size() <= kMaxMessageBytes && "encode: message too large");
    return out;
}

/// Hello and Refuse: an Envelope exactly as protocol version 1 built it,
/// padding included (version 1 requires a length that is a multiple of 4).
std::vector<std::uint8_t> finish_envelope(fb::FlatBufferBuilder& b, w::Handshake type, fb::Offset<void> body) {
    w::FinishEnvelopeBuffer(b, w::CreateEnvelope(b, type, body));
    return {b.GetBufferPointer(), b.GetBufferPointer() + b.GetSize()};
}

struct Encoder {
    fb::FlatBufferBuilder& b;

    std::vector<std::uint8_t> operator()(const Hello& m) const {
        assert_text(m.name, kMaxNameBytes);
        const auto name = b.CreateString(m.name);
        const auto tok = token(b, m.reconnect_token);
        assert(m.connect_token.size() <= kMaxConnectTokenBytes && "encode: connect token too long");
        const auto connect = m.connect_token.empty() ? 0 : b.CreateVector(m.connect_token);
        return finish_envelope(b, w::Handshake_Hello,
                               w::CreateHello(b, m.protocol_version, name, tok, connect, m.observe).Union());
    }
    std::vector<std::uint8_t> operator()(const Welcome& m) const {
        assert(m.max_players >= 1 && m.max_players <= kMaxSlots && m.slot < m.max_players);
        assert(m.tick_rate_hz >= 1 && m.tick_rate_hz <= kMaxRateHz);
        assert(m.snapshot_rate_hz >= 1 && m.snapshot_rate_hz <= kMaxRateHz);
        assert(m.track_bytes <= kMaxTrackBytes);
        assert_text(m.track_name, kMaxTrackNameBytes);
        const auto track = b.CreateString(m.track_name);
        const auto tok = token(b, m.reconnect_token);
        const auto physics = m.physics ? encode_physics(b, *m.physics) : 0;
        return finish<Welcome>(b, w::CreateWelcome(b, m.protocol_version, m.slot, m.max_players, m.tick_rate_hz,
                                                   m.snapshot_rate_hz, track, m.track_identity, m.physics_hash,
                                                   m.server_tick, tok, physics, m.observer, m.track_bytes));
    }
    std::vector<std::uint8_t> operator()(const Refuse& m) const {
        assert_text(m.reason, kMaxReasonBytes);
        return finish_envelope(b, w::Handshake_Refuse, w::CreateRefuse(b, b.CreateString(m.reason), m.code).Union());
    }
    std::vector<std::uint8_t> operator()(const InputBatch& m) const { return packed_message<InputBatch>(packed::pack(m)); }
    std::vector<std::uint8_t> operator()(const Snapshot& m) const { return packed_message<Snapshot>(packed::pack(m)); }
    std::vector<std::uint8_t> operator()(const RaceStatus& m) const {
        assert(m.players.size() <= static_cast<std::size_t>(kMaxSlots) && m.laps >= 1);
        std::vector<fb::Offset<w::PlayerInfo>> players;
        for (const PlayerInfo& p : m.players) {
            assert(p.slot < kMaxSlots);
            assert_text(p.name, kMaxNameBytes);
            players.push_back(w::CreatePlayerInfo(b, p.slot, b.CreateString(p.name), p.spectating));
        }
        const auto list = b.CreateVector(players);
        return finish<RaceStatus>(b, w::CreateRaceStatus(b, static_cast<w::RacePhase>(m.phase), m.race_number,
                                                         m.start_tick, m.laps, list));
    }
    std::vector<std::uint8_t> operator()(const Results& m) const {
        assert(m.standings.size() <= static_cast<std::size_t>(kMaxSlots));
        std::vector<fb::Offset<w::StandingEntry>> standings;
        for (const StandingEntry& e : m.standings) {
            assert(e.slot < kMaxSlots && std::isfinite(e.finish_time_s) && e.finish_time_s >= 0);
            assert_text(e.name, kMaxNameBytes);
            standings.push_back(
                w::CreateStandingEntry(b, e.slot, b.CreateString(e.name), e.finished, e.lap, e.finish_time_s));
        }
        const auto list = b.CreateVector(standings);
        return finish<Results>(b, w::CreateResults(b, m.race_number, list, m.state_hash));
    }
    std::vector<std::uint8_t> operator()(const Goodbye& m) const {
        assert_text(m.reason, kMaxReasonBytes);
        return finish<Goodbye>(b, w::CreateGoodbye(b, b.CreateString(m.reason), m.code));
    }
    std::vector<std::uint8_t> operator()(const SnapshotAck& m) const {
        return finish<SnapshotAck>(b, w::CreateSnapshotAck(b, m.ack_snapshot_tick));
    }
    std::vector<std::uint8_t> operator()(const TrackRequest& m) const {
        return finish<TrackRequest>(b, w::CreateTrackRequest(b, m.offset));
    }
    std::vector<std::uint8_t> operator()(const TrackChunk& m) const {
        assert(!m.bytes.empty() && m.bytes.size() <= kTrackChunkBytes &&
               std::uint64_t{m.offset} + m.bytes.size() <= kMaxTrackBytes && "encode: bad track chunk");
        return finish<TrackChunk>(b, w::CreateTrackChunk(b, m.offset, b.CreateVector(m.bytes)));
    }
};

// ---------------------------------------------------------------- decode

bool decode_body(const w::Hello& t, Message& out, Check& c) {
    Hello m;
    m.protocol_version = t.protocol_version();
    if (!c.text(t.name(), kMaxNameBytes, "Hello.name", m.name)) return false;
    if (!c.token(t.reconnect_token(), "Hello.reconnect_token", m.reconnect_token)) return false;
    if (const auto* ct = t.connect_token()) {
        if (ct->size() > kMaxConnectTokenBytes) return c.fail("Hello.connect_token", "too long");
        m.connect_token.assign(ct->begin(), ct->end());
    }
    if (!c.flag(&t, w::Hello::VT_OBSERVE, "Hello.observe", m.observe)) return false;
    out = std::move(m);
    return true;
}

bool decode_body(const w::Welcome& t, Message& out, Check& c) {
    Welcome m;
    m.protocol_version = t.protocol_version();
    m.max_players = t.max_players();
    if (m.max_players < 1 || m.max_players > kMaxSlots) return c.fail("Welcome.max_players", "out of range");
    m.slot = t.slot();
    if (m.slot >= m.max_players) return c.fail("Welcome.slot", "not below max_players");
    m.tick_rate_hz = t.tick_rate_hz();
    if (m.tick_rate_hz < 1 || m.tick_rate_hz > kMaxRateHz) return c.fail("Welcome.tick_rate_hz", "out of range");
    m.snapshot_rate_hz = t.snapshot_rate_hz();
    if (m.snapshot_rate_hz < 1 || m.snapshot_rate_hz > kMaxRateHz)
        return c.fail("Welcome.snapshot_rate_hz", "out of range");
    if (!c.text(t.track_name(), kMaxTrackNameBytes, "Welcome.track_name", m.track_name)) return false;
    m.track_identity = t.track_identity();
    m.physics_hash = t.physics_hash();
    m.server_tick = t.server_tick();
    if (!c.token(t.reconnect_token(), "Welcome.reconnect_token", m.reconnect_token)) return false;
    if (t.physics() != nullptr) {
        PhysicsSettings p;
        std::string why;
        if (!decode_physics(*t.physics(), p, why)) return c.fail("Welcome.physics", why.c_str());
        if (p.tick_rate_hz != m.tick_rate_hz)
            return c.fail("Welcome.physics.tick_rate_hz", "differs from Welcome.tick_rate_hz");
        m.physics = p;
    }
    if (!c.flag(&t, w::Welcome::VT_OBSERVER, "Welcome.observer", m.observer)) return false;
    m.track_bytes = t.track_bytes();
    if (m.track_bytes > kMaxTrackBytes) return c.fail("Welcome.track_bytes", "above kMaxTrackBytes");
    out = std::move(m);
    return true;
}

bool decode_body(const w::Refuse& t, Message& out, Check& c) {
    Refuse m;
    if (!c.text(t.reason(), kMaxReasonBytes, "Refuse.reason", m.reason)) return false;
    m.code = t.code();
    out = std::move(m);
    return true;
}

/// A packed message (see packed_message()): InputBatch or Snapshot.
template <typename M>
bool decode_packed(const std::uint8_t* data, std::size_t size, Message& out, Check& c) {
    const char* const what = std::is_same_v<M, Snapshot> ? "Snapshot.payload" : "InputBatch.payload";
    for (std::size_t i = 0; i < sizeof(fb::uoffset_t); ++i)
        if (data[i] != 0) return c.fail("message", "a packed message starts with 4 zero bytes");
    if (size <= kPackedHeaderBytes) return c.fail(what, "missing");
    const std::span<const std::uint8_t> payload(data + kPackedHeaderBytes, size - kPackedHeaderBytes);
    if (std::is_same_v<M, Snapshot> && payload.size() > kMaxSnapshotPayloadBytes) return c.fail(what, "too long");
    M m;
    if (!packed::unpack(payload, m, c.error())) return false;
    out = std::move(m);
    return true;
}

bool decode_body(const w::RaceStatus& t, Message& out, Check& c) {
    RaceStatus m;
    if (!c.phase(t.phase(), "RaceStatus.phase", m.phase)) return false;
    m.race_number = t.race_number();
    m.start_tick = t.start_tick();
    m.laps = t.laps();
    if (m.laps < 1) return c.fail("RaceStatus.laps", "zero");
    const auto* players = t.players();
    if (!players) return c.fail("RaceStatus.players", "missing");
    if (players->size() > static_cast<fb::uoffset_t>(kMaxSlots)) return c.fail("RaceStatus.players", "too many");
    std::uint64_t seen = 0;
    for (fb::uoffset_t i = 0; i < players->size(); ++i) {
        const w::PlayerInfo* p = players->Get(i);
        const std::string field = "RaceStatus.players[" + std::to_string(i) + "]";
        if (!p) return c.fail(field, "missing");
        PlayerInfo info;
        info.slot = p->slot();
        if (!c.slot(info.slot, seen, field + ".slot")) return false;
        if (!c.text(p->name(), kMaxNameBytes, field + ".name", info.name)) return false;
        if (!c.flag(p, w::PlayerInfo::VT_SPECTATING, field + ".spectating", info.spectating)) return false;
        m.players.push_back(std::move(info));
    }
    out = std::move(m);
    return true;
}

bool decode_body(const w::Results& t, Message& out, Check& c) {
    Results m;
    m.race_number = t.race_number();
    m.state_hash = t.state_hash();
    const auto* standings = t.standings();
    if (!standings) return c.fail("Results.standings", "missing");
    if (standings->size() > static_cast<fb::uoffset_t>(kMaxSlots)) return c.fail("Results.standings", "too many");
    std::uint64_t seen = 0;
    for (fb::uoffset_t i = 0; i < standings->size(); ++i) {
        const w::StandingEntry* e = standings->Get(i);
        const std::string field = "Results.standings[" + std::to_string(i) + "]";
        if (!e) return c.fail(field, "missing");
        StandingEntry s;
        s.slot = e->slot();
        if (!c.slot(s.slot, seen, field + ".slot")) return false;
        if (!c.text(e->name(), kMaxNameBytes, field + ".name", s.name)) return false;
        if (!c.flag(e, w::StandingEntry::VT_FINISHED, field + ".finished", s.finished)) return false;
        s.lap = e->lap();
        s.finish_time_s = e->finish_time_s();
        if (!(std::isfinite(s.finish_time_s) && s.finish_time_s >= 0))
            return c.fail(field + ".finish_time_s", "not a finite time >= 0");
        m.standings.push_back(std::move(s));
    }
    out = std::move(m);
    return true;
}

bool decode_body(const w::Goodbye& t, Message& out, Check& c) {
    Goodbye m;
    if (!c.text(t.reason(), kMaxReasonBytes, "Goodbye.reason", m.reason)) return false;
    m.code = t.code();
    out = std::move(m);
    return true;
}

bool decode_body(const w::SnapshotAck& t, Message& out, Check&) {
    out = SnapshotAck{t.ack_snapshot_tick()};
    return true;
}

bool decode_body(const w::TrackRequest& t, Message& out, Check&) {
    out = TrackRequest{t.offset()};
    return true;
}

bool decode_body(const w::TrackChunk& t, Message& out, Check& c) {
    const auto* bytes = t.bytes();
    if (!bytes) return c.fail("TrackChunk.bytes", "missing");
    if (bytes->size() == 0 || bytes->size() > kTrackChunkBytes) return c.fail("TrackChunk.bytes", "not 1..kTrackChunkBytes long");
    if (std::uint64_t{t.offset()} + bytes->size() > kMaxTrackBytes)
        return c.fail("TrackChunk.offset", "ends past kMaxTrackBytes");
    out = TrackChunk{t.offset(), std::vector<std::uint8_t>(bytes->begin(), bytes->end())};
    return true;
}

/// Verifies the buffer as message M and decodes it.
template <typename M>
bool decode_as(const std::uint8_t* data, std::size_t size, Message& out, Check& c) {
    using T = typename Wire<M>::Table;
    if (!verifies<T>(data, size, Wire<M>::kId)) return c.fail("message", "malformed flatbuffer (verification failed)");
    return decode_body(*fb::GetRoot<T>(data), out, c);
}

/// Hello or Refuse in an Envelope, with the rules of protocol version 1.
bool decode_envelope(const std::uint8_t* data, std::size_t size, Message& out, Check& c) {
    // Every finished flatbuffer is a whole number of 4-byte words (the
    // builder aligns to its 4-byte offsets), and Envelopes are sent as
    // built: this also catches truncations that only cut padding.
    if (size % 4 != 0) return c.fail("message", "length not a multiple of 4 (truncated?)");
    if (!verifies<w::Envelope>(data, size, w::EnvelopeIdentifier()))
        return c.fail("message", "malformed flatbuffer (verification failed)");
    const w::Envelope* env = w::GetEnvelope(data);
    switch (env->body_type()) {
        case w::Handshake_Hello:
            if (const auto* hello = env->body_as_Hello()) return decode_body(*hello, out, c);
            break;
        case w::Handshake_Refuse:
            if (const auto* refuse = env->body_as_Refuse()) return decode_body(*refuse, out, c);
            break;
        default: return c.fail("Envelope.body_type", "not Hello or Refuse");
    }
    return c.fail("Envelope.body", "missing");
}

using DecodeFn = bool (*)(const std::uint8_t*, std::size_t, Message&, Check&);
struct Kind {
    const char* id;
    DecodeFn decode;
};
template <typename M>
constexpr Kind kind() {
    return {Wire<M>::kId, decode_as<M>};
}
/// Every identifier: the Envelope's ("JTR1", the schema's file_identifier)
/// for Hello and Refuse, then one per other message.
constexpr Kind kKinds[] = {{"JTR1", decode_envelope},
                           kind<Welcome>(),
                           {Wire<InputBatch>::kId, decode_packed<InputBatch>},
                           {Wire<Snapshot>::kId, decode_packed<Snapshot>},
                           kind<RaceStatus>(),
                           kind<Results>(),
                           kind<Goodbye>(),
                           kind<SnapshotAck>(),
                           kind<TrackRequest>(),
                           kind<TrackChunk>()};
static_assert(std::size(kKinds) == std::variant_size_v<Message> - 1);

}  // namespace

const char* to_string(RacePhase p) {
    switch (p) {
        case RacePhase::lobby: return "lobby";
        case RacePhase::countdown: return "countdown";
        case RacePhase::racing: return "racing";
        case RacePhase::finished: return "finished";
    }
    return "unknown";
}

std::vector<std::uint8_t> encode(const Message& m) {
    fb::FlatBufferBuilder b(256);
    return std::visit(Encoder{b}, m);
}

bool decode(std::span<const std::uint8_t> bytes, Message& out, std::string& error) {
    if (bytes.empty()) {
        error = "message: empty";
        return false;
    }
    if (bytes.size() > kMaxMessageBytes) {
        error = "message: larger than kMaxMessageBytes";
        return false;
    }
    // The file identifier, after the root offset, names the message.
    const Kind* kind = nullptr;
    if (bytes.size() >= sizeof(fb::uoffset_t) + fb::kFileIdentifierLength) {
        const std::uint8_t* id = bytes.data() + sizeof(fb::uoffset_t);
        for (const Kind& k : kKinds)
            if (std::memcmp(id, k.id, fb::kFileIdentifierLength) == 0) kind = &k;
    }
    if (!kind) {
        error = "message: unknown file identifier";
        return false;
    }
    // flatbuffers reads scalars in place: they must be aligned in memory.
    std::vector<std::uint64_t> aligned;
    const std::uint8_t* data = bytes.data();
    if (reinterpret_cast<std::uintptr_t>(data) % alignof(std::uint64_t) != 0) {
        aligned.resize((bytes.size() + 7) / 8);
        std::memcpy(aligned.data(), bytes.data(), bytes.size());
        data = reinterpret_cast<const std::uint8_t*>(aligned.data());
    }
    Check c(error);
    return kind->decode(data, bytes.size(), out, c);
}

bool valid_text(std::string_view text) { return clean_utf8(text); }

std::uint64_t physics_hash(const PhysicsSettings& s) {
    // FNV-1a over every field in declaration order, raw bits of doubles: the
    // core's fingerprint, so that there is one list of fields to maintain.
    return physics_fingerprint(s);
}

}  // namespace jetrace::proto

namespace jetrace::proto {

bool input_batch_ticks(std::span<const std::uint8_t> bytes, std::uint32_t& first, std::uint32_t& last) {
    Message m;
    std::string error;
    if (!decode(bytes, m, error)) return false;
    const auto* batch = std::get_if<InputBatch>(&m);
    if (!batch || batch->inputs.empty()) return false;
    first = batch->first_tick;
    last = batch->first_tick + static_cast<std::uint32_t>(batch->inputs.size() - 1);
    return true;
}

}  // namespace jetrace::proto
