// Replays (format version 2): recorded offline races verify by
// re-simulation; a cut at every record boundary reads as incomplete and a
// cut inside a record as truncated, never as a shorter race; a flipped byte
// in any record is corruption; tampering that keeps the CRCs right is caught
// by the checkpoints, the trailer or the signature; the desync finder names
// the first differing tick, cars and fields; SyncTest holds on real races.
#include "jetrace/ai/offline_race.hpp"
#include "jetrace/auth/connect_token.hpp"
#include "jetrace/core/crc32c.hpp"
#include "jetrace/core/state_bytes.hpp"
#include "jetrace/replay/diff.hpp"
#include "jetrace/replay/scene_for.hpp"
#include "jetrace/replay/synctest.hpp"
#include "jetrace/replay/writer.hpp"
#include "jetrace/tracks/builtin_tracks.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <fstream>
#include <iterator>

#include <unistd.h>

namespace {

using namespace jetrace;
using namespace jetrace::replay;
using Bytes = std::vector<std::uint8_t>;

Scene ring_scene(const PhysicsSettings& physics = {}) {
    Track track;
    EXPECT_TRUE(make_builtin_track("ring", track));
    return Scene::make(std::move(track), physics);
}

std::string temp_path(const std::string& name) {
    return (std::filesystem::temp_directory_path() / ("jetrace_test_" + std::to_string(::getpid()) + "_" + name)).string();
}

Bytes slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return Bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

struct Recording {
    Bytes bytes;
    std::uint64_t final_hash = 0;
};

/// An offline AI race on `run_on` recorded as if by a build whose physics
/// are `claimed` (the default): a different `run_on` is another build.
Recording record(const Scene& run_on, int cars, double seconds, std::uint64_t seed,
                 const std::optional<SigningKey>& key = std::nullopt) {
    const std::string path = temp_path("rec_" + std::to_string(seed) + ".jtr");
    WorldState st = start_race(run_on, cars, 2);
    Header h = header_for(run_on, st);
    h.physics_hash = physics_fingerprint(PhysicsSettings{});
    h.names.assign(static_cast<std::size_t>(cars), "driver");
    Writer w;
    EXPECT_TRUE(w.open(path, h, key)) << w.error();
    Recorder rec(w);
    StepScratch scratch;
    run_ai(Course(run_on), st, skills_for(cars, seed), static_cast<std::uint32_t>(seconds * 120), false, scratch, &rec);
    const Trailer t = trailer_for(run_on, st, EndReason::time_limit);
    EXPECT_TRUE(w.finish(t)) << w.error();
    Recording r{slurp(path), t.final_state_hash};
    std::filesystem::remove(path);
    return r;
}

/// Re-simulates `a`'s inputs on `build` and records that (another build's
/// re-simulation of the same race).
Bytes resimulate(const Bytes& a, const Scene& build) {
    const std::string path = temp_path("resim.jtr");
    SpanSource src(a);
    Scanner sc(src);
    Event ev;
    Writer w;
    WorldState st;
    StepScratch scratch;
    while (sc.next(ev)) {
        if (ev.kind == RecordKind::header) {
            st = ev.header.initial;
            EXPECT_TRUE(w.open(path, ev.header)) << w.error();
        } else if (ev.kind == RecordKind::tick) {
            w.record_tick(ev.tick.tick, ev.tick.removed, ev.tick.inputs);
            step(build, st, ev.tick.inputs, scratch);
            w.stepped(st);
        } else if (ev.kind == RecordKind::trailer) {
            Trailer t = ev.trailer;
            t.final_state_hash = state_hash(st);
            t.results = results_of(build, st);
            EXPECT_TRUE(w.finish(t)) << w.error();
        }
    }
    EXPECT_TRUE(sc.ok()) << sc.failure().message;
    Bytes out = slurp(path);
    std::filesystem::remove(path);
    return out;
}

const Scene& ring() {
    static const Scene scene = ring_scene();
    return scene;
}

SceneFor ring_for() {
    return [](const Header&, std::string&) { return &ring(); };
}

Verdict check(const Bytes& b, const VerifyOptions& o = {}) {
    SpanSource src(b);
    return verify(src, ring_for(), o);
}

/// Byte offsets where each record starts, with its kind.
std::vector<std::pair<std::size_t, RecordKind>> records(const Bytes& b) {
    std::vector<std::pair<std::size_t, RecordKind>> out;
    std::size_t off = kMagic.size();
    while (off + kRecordHeadBytes <= b.size()) {
        const std::uint32_t len = b[off + 1] | b[off + 2] << 8 | b[off + 3] << 16 | std::uint32_t{b[off + 4]} << 24;
        out.emplace_back(off, static_cast<RecordKind>(b[off]));
        off += kRecordHeadBytes + len + kRecordTailBytes;
    }
    return out;
}

/// Replaces the payload byte `at` (offset in the file) and fixes the record's CRC.
void tamper(Bytes& b, std::size_t record_at, std::size_t at, std::uint8_t value) {
    const std::uint32_t len = b[record_at + 1] | b[record_at + 2] << 8 | b[record_at + 3] << 16 |
                              std::uint32_t{b[record_at + 4]} << 24;
    b[at] = value;
    const std::uint32_t crc = crc32c(std::span<const std::uint8_t>(b).subspan(record_at, kRecordHeadBytes + len));
    for (int i = 0; i < 4; ++i) b[record_at + kRecordHeadBytes + len + i] = static_cast<std::uint8_t>(crc >> (8 * i));
}

TEST(Replay, Crc32cKnownValue) {
    const std::string s = "123456789";
    EXPECT_EQ(crc32c({reinterpret_cast<const std::uint8_t*>(s.data()), s.size()}), 0xE3069283u);
}

TEST(Replay, RecordedRaceVerifiesWithEveryCheckpointAndKeyframe) {
    const Recording r = record(ring(), 4, 12, 1);
    const Verdict v = check(r.bytes);
    EXPECT_TRUE(v.ok) << to_json(v);
    EXPECT_EQ(v.state_hash, r.final_hash);
    EXPECT_EQ(v.final_tick, 1440u);
    EXPECT_EQ(v.checkpoints, 12u);
    EXPECT_EQ(v.keyframes, 2u);
    EXPECT_TRUE(v.complete);
    EXPECT_EQ(v.end_reason, "time limit");
    EXPECT_EQ(v.signature, "absent");
}

TEST(Replay, CutAtEveryRecordBoundaryIsIncompleteNeverAShorterRace) {
    const Recording r = record(ring(), 2, 3, 2);
    const auto recs = records(r.bytes);
    ASSERT_GT(recs.size(), 360u);
    for (const auto& [at, kind] : recs) {
        const Verdict v = check(Bytes(r.bytes.begin(), r.bytes.begin() + static_cast<std::ptrdiff_t>(at)));
        ASSERT_FALSE(v.ok) << "cut at byte " << at;
        ASSERT_EQ(v.problem, "incomplete") << "cut at byte " << at << ": " << to_json(v);
        ASSERT_FALSE(v.complete);
    }
    // Inside a record: truncated.
    for (const auto& [at, kind] : recs) {
        const Verdict v = check(Bytes(r.bytes.begin(), r.bytes.begin() + static_cast<std::ptrdiff_t>(at) + 3));
        ASSERT_EQ(v.problem, "truncated") << "cut at byte " << at + 3;
    }
}

TEST(Replay, AFlippedByteInAnyRecordIsCorruptionNotTruncation) {
    const Recording r = record(ring(), 2, 6, 3);
    std::map<RecordKind, int> flipped;
    for (const auto& [at, kind] : records(r.bytes)) {
        if (flipped[kind]++ >= 2) continue;  // every byte of the first two records of each kind
        const std::size_t end = at + kRecordHeadBytes + (r.bytes[at + 1] | r.bytes[at + 2] << 8) + kRecordTailBytes;
        for (std::size_t i = at; i < end; ++i) {
            Bytes b = r.bytes;
            b[i] ^= 0x10;
            const Verdict v = check(b);
            ASSERT_FALSE(v.ok) << "byte " << i;
            // A length flipped upwards runs past the end of the file: that reads as a cut.
            const bool length = i >= at + 1 && i < at + kRecordHeadBytes;
            ASSERT_TRUE(v.problem == "corrupt" || (length && v.problem == "truncated")) << "byte " << i << ": " << to_json(v);
        }
    }
    EXPECT_EQ(flipped.size(), 5u);  // header, tick, checkpoint, keyframe, trailer
}

TEST(Replay, TamperingThatKeepsTheChecksumsIsCaughtByTheSimulation) {
    const Recording r = record(ring(), 2, 6, 4);
    const auto recs = records(r.bytes);
    const auto first = [&](RecordKind k) {
        for (const auto& [at, kind] : recs) {
            if (kind == k) return at;
        }
        return std::size_t{0};
    };
    {  // an input of the first tick record: the checkpoints disagree
        Bytes b = r.bytes;
        const std::size_t t = first(RecordKind::tick);
        tamper(b, t, t + kRecordHeadBytes + 4 + 1 + 2, 0x00);
        const Verdict v = check(b);
        EXPECT_EQ(v.problem, "checkpoint_mismatch") << to_json(v);
        EXPECT_EQ(v.tick, 120u);
        EXPECT_FALSE(v.cars.empty());
        ASSERT_TRUE(v.fields_tick.has_value()) << "followed to the next keyframe";
        EXPECT_EQ(*v.fields_tick, 600u);
        EXPECT_FALSE(v.fields.empty());
    }
    {  // the trailer's final hash
        Bytes b = r.bytes;
        const std::size_t e = first(RecordKind::trailer);
        tamper(b, e, e + kRecordHeadBytes + 4, static_cast<std::uint8_t>(b[e + kRecordHeadBytes + 4] ^ 1));
        EXPECT_EQ(check(b).problem, "final_hash_mismatch");
    }
    {  // the trailer's results: the first place's lap
        Bytes b = r.bytes;
        const std::size_t e = first(RecordKind::trailer);
        const std::size_t lap = e + kRecordHeadBytes + 4 + 8 + 1 + 8 + 1 + 2 + 2;
        tamper(b, e, lap, static_cast<std::uint8_t>(b[lap] + 1));
        EXPECT_EQ(check(b).problem, "results_mismatch");
    }
    {  // a checkpoint dropped whole: out of sequence
        Bytes b = r.bytes;
        const std::size_t c = first(RecordKind::checkpoint);
        const std::size_t len = b[c + 1] | b[c + 2] << 8;
        b.erase(b.begin() + static_cast<std::ptrdiff_t>(c), b.begin() + static_cast<std::ptrdiff_t>(c + kRecordHeadBytes + len + kRecordTailBytes));
        EXPECT_EQ(check(b).problem, "out_of_sequence");
    }
}

TEST(Replay, SignaturesAreCheckedAgainstTheTrustedKey) {
    if (!signing_available()) GTEST_SKIP() << "built without libsodium";
    const auth::KeyPair keys = auth::generate_key_pair();
    const Recording r = record(ring(), 2, 3, 5, keys.secret_key);
    VerifyOptions trusted;
    trusted.trusted_key = keys.public_key;
    Verdict v = check(r.bytes, trusted);
    EXPECT_TRUE(v.ok) << to_json(v);
    EXPECT_EQ(v.signature, "valid");
    EXPECT_TRUE(v.signer_trusted);
    VerifyOptions other;
    other.trusted_key = auth::generate_key_pair().public_key;
    EXPECT_EQ(check(r.bytes, other).problem, "untrusted_signer");
    // A player's name in the header changes nothing simulated: only the signature sees it.
    Bytes b = r.bytes;
    const std::size_t h = kMagic.size();
    const auto name_at = std::search(b.begin(), b.end(), std::begin("driver"), std::end("driver") - 1) - b.begin();
    tamper(b, h, static_cast<std::size_t>(name_at), 'D');
    v = check(b, trusted);
    EXPECT_EQ(v.problem, "signature_invalid") << to_json(v);
    // Unsigned, when a key is required.
    EXPECT_EQ(check(record(ring(), 2, 1, 6).bytes, trusted).problem, "signature_missing");
}

TEST(Replay, ExpectedHashAndReaderLimits) {
    const Recording r = record(ring(), 2, 1, 7);
    VerifyOptions o;
    o.expect_hash = r.final_hash ^ 1;
    EXPECT_EQ(check(r.bytes, o).problem, "expect_mismatch");
    Bytes old(r.bytes);
    old[7] = '1';
    EXPECT_EQ(check(old).problem, "old_version");
    EXPECT_EQ(check(Bytes{'n', 'o', 'p', 'e'}).problem, "not_a_replay");
    FileSource f;
    std::string error;
    EXPECT_FALSE(f.open(std::filesystem::temp_directory_path().string(), error, kMaxFileBytes));
    EXPECT_NE(error.find("directory"), std::string::npos) << error;
    EXPECT_FALSE(f.open("/dev/zero", error, kMaxFileBytes));
    EXPECT_NE(error.find("not a regular file"), std::string::npos) << error;
    const std::string path = temp_path("big.jtr");
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(r.bytes.data()),
                                                static_cast<std::streamsize>(r.bytes.size()));
    EXPECT_FALSE(f.open(path, error, r.bytes.size() - 1));
    EXPECT_NE(error.find("more than"), std::string::npos) << error;
    std::filesystem::remove(path);
}

TEST(ReplayDiff, AnotherBuildIsFoundAtItsFirstCheckpointWithItsFields) {
    PhysicsSettings other;
    other.thrust_mps2 += 0.01;  // a build whose thrust comes out slightly otherwise
    const Scene other_build = ring_scene(other);
    const Recording a = record(ring(), 3, 12, 8);
    const Recording b{resimulate(a.bytes, other_build), 0};
    SpanSource sa(a.bytes), sb(b.bytes);
    const DiffReport d = diff_replays(sa, sb, ring_for());
    ASSERT_EQ(d.verdict, "desync") << to_json(d);
    ASSERT_TRUE(d.first_differing_tick.has_value());
    EXPECT_EQ(*d.first_differing_tick % 120, 0u);
    EXPECT_FALSE(d.cars.empty());
    ASSERT_TRUE(d.fields_tick.has_value());
    EXPECT_GE(*d.fields_tick, *d.first_differing_tick);
    ASSERT_FALSE(d.fields.empty());
    // Thrust moves the car: its position comes first in field order.
    EXPECT_EQ(d.fields.front().field.rfind("position.", 0), 0u) << describe(d.fields.front());
    EXPECT_NE(std::find(d.cars.begin(), d.cars.end(), d.fields.front().slot), d.cars.end());
    EXPECT_EQ(d.this_build, "a");
    // The other build's recording against this build: the same tick.
    const Verdict v = check(b.bytes);
    const DiffReport rebuilt = diff_against_build(v);
    EXPECT_EQ(rebuilt.verdict, "desync");
    EXPECT_EQ(rebuilt.first_differing_tick, d.first_differing_tick);
}

TEST(ReplayDiff, DifferentInputsAreNotADesync) {
    const Recording a = record(ring(), 2, 2, 9);
    const Recording b = record(ring(), 2, 2, 10);
    SpanSource sa(a.bytes), sb(b.bytes), sa2(a.bytes);
    const DiffReport d = diff_replays(sa, sb, ring_for());
    EXPECT_EQ(d.verdict, "inputs_differ") << to_json(d);
    EXPECT_TRUE(d.input_tick.has_value());
    const DiffReport same = diff_replays(sa2, *std::make_unique<SpanSource>(a.bytes), ring_for());
    EXPECT_EQ(same.verdict, "identical") << to_json(same);
}

TEST(Synctest, HoldsOnARecordedRace) {
    const Recording r = record(ring(), 4, 6, 11);
    SpanSource src(r.bytes);
    const SynctestReport s = synctest(src, ring_for(), 8);
    EXPECT_TRUE(s.ok) << to_json(s);
    EXPECT_EQ(s.ticks, 720u);
    EXPECT_EQ(s.fresh_checks, 720u);
    EXPECT_EQ(s.rollback_checks, 90u);
}

}  // namespace
