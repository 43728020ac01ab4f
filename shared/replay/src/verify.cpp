#include "jetrace/replay/verify.hpp"

#include "jetrace/core/state_bytes.hpp"

#include <algorithm>

namespace jetrace::replay {

std::string hex(std::span<const std::uint8_t> bytes) {
    static constexpr char kDigits[] = "0123456789abcdef";
    std::string s;
    for (std::uint8_t b : bytes) {
        s.push_back(kDigits[b >> 4]);
        s.push_back(kDigits[b & 15]);
    }
    return s;
}

std::vector<int> differing_cars(const Checkpoint& a, const Checkpoint& b) {
    std::vector<int> out;
    for (std::size_t s = 0; s < a.car_hashes.size() && s < b.car_hashes.size(); ++s) {
        if (a.car_hashes[s] != b.car_hashes[s]) out.push_back(static_cast<int>(s));
    }
    return out;
}

namespace {

class Verification {
public:
    Verification(ByteSource& source, const SceneFor& scene_for, const VerifyOptions& o)
        : scanner_(source), scene_for_(scene_for), options_(o) {}

    Verdict run() {
        Event ev;
        while (!stop_ && scanner_.next(ev)) handle(ev);
        v_.final_tick = state_.tick;
        v_.state_hash = state_hash(state_);
        v_.bytes = scanner_.bytes_read();
        if (v_.problem.empty() && !scanner_.ok()) {
            const ScanFailure& f = scanner_.failure();
            fail(problem_name(f.problem), f.byte_offset, f.message);
        }
        if (v_.problem.empty()) check_requirements();
        v_.ok = v_.problem.empty();
        return v_;
    }

private:
    void fail(const std::string& problem, std::uint64_t at, const std::string& message) {
        if (!v_.problem.empty()) return;
        v_.problem = problem;
        v_.byte_offset = at;
        v_.tick = state_.tick;
        v_.message = message;
    }

    void handle(Event& ev) {
        if (located_ && ev.kind != RecordKind::tick && ev.kind != RecordKind::keyframe) return;
        switch (ev.kind) {
            case RecordKind::header: header(ev); break;
            case RecordKind::tick: tick(ev.tick); break;
            case RecordKind::checkpoint: checkpoint(ev); break;
            case RecordKind::keyframe: keyframe(ev); break;
            case RecordKind::trailer: trailer(ev); break;
            case RecordKind::signature: signature(ev); break;
        }
    }

    void header(const Event& ev) {
        const Header& h = ev.header;
        v_.track = h.track_name;
        v_.race_number = h.race_number;
        v_.initial_tick = h.initial.tick;
        state_ = h.initial;
        std::string error;
        scene_ = scene_for_(h, error);
        if (!scene_) return stop("track", ev.byte_offset, error);
        if (h.track_identity != scene_->track.identity()) {
            return stop("track", ev.byte_offset,
                        "the replay was recorded on a different track than '" + scene_->track.name + "' (identity mismatch)");
        }
        if (h.physics_hash != physics_fingerprint(scene_->physics) || h.tick_rate_hz != scene_->physics.tick_rate_hz) {
            return stop("physics", ev.byte_offset, "the replay was recorded with other physics settings than this build's");
        }
        const auto gates = static_cast<std::int32_t>(scene_->track.checkpoints.size());
        for (const CarState& c : h.initial.cars) {
            if (c.next_checkpoint >= gates || c.respawn_checkpoint >= gates) {
                return stop("malformed", ev.byte_offset, "the initial state names a gate the track does not have");
            }
        }
    }

    void stop(const std::string& problem, std::uint64_t at, const std::string& message) {
        fail(problem, at, message);
        stop_ = true;
    }

    void tick(const TickRecord& t) {
        for (std::uint8_t s : t.removed) remove_car(state_, s);
        step(*scene_, state_, t.inputs, scratch_);
    }

    void checkpoint(const Event& ev) {
        ++v_.checkpoints;
        const Checkpoint mine = checkpoint_of(state_);
        if (mine.state_hash == ev.checkpoint.state_hash && mine.car_hashes == ev.checkpoint.car_hashes) {
            v_.last_good_checkpoint = mine.tick;
            return;
        }
        v_.cars = differing_cars(ev.checkpoint, mine);
        fail("checkpoint_mismatch", ev.byte_offset,
             "the re-simulated world differs from the recording at tick " + std::to_string(mine.tick) +
                 (v_.last_good_checkpoint ? " (it agreed at tick " + std::to_string(*v_.last_good_checkpoint) + ")" : ""));
        located_ = true;  // read on to the next keyframe to name the fields
    }

    void keyframe(const Event& ev) {
        ++v_.keyframes;
        if (same_state(ev.keyframe, state_)) {
            if (located_) stop_ = true;
            return;
        }
        v_.fields_tick = state_.tick;
        v_.fields = diff_states(ev.keyframe, state_, options_.max_fields);
        fail("keyframe_mismatch", ev.byte_offset,
             "the recorded keyframe of tick " + std::to_string(state_.tick) + " differs from the re-simulated world");
        stop_ = true;
    }

    void trailer(const Event& ev) {
        const Trailer& t = ev.trailer;
        for (std::uint8_t s : t.removed) remove_car(state_, s);
        v_.complete = true;
        v_.end_reason = end_reason_name(t.reason);
        v_.results = t.results;
        if (t.final_state_hash != state_hash(state_)) {
            return stop("final_hash_mismatch", ev.byte_offset,
                        "the trailer's final state hash " + hash_hex(t.final_state_hash) + " is not the re-simulated " +
                            hash_hex(state_hash(state_)));
        }
        if (t.results != results_of(*scene_, state_)) {
            stop("results_mismatch", ev.byte_offset, "the trailer's results are not the re-simulated race's standings");
        }
    }

    void signature(const Event& ev) {
        const Signature& s = ev.signature;
        v_.signer = hex(s.public_key);
        v_.signer_trusted = options_.trusted_key && *options_.trusted_key == s.public_key;
        if (!signing_available()) {
            v_.signature = "unchecked";
            return;
        }
        const bool valid = scanner_.signed_bytes().verify(s.signature, s.public_key);
        v_.signature = valid ? "valid" : "invalid";
        if (!valid) stop("signature_invalid", ev.byte_offset, "the signature does not match the file's bytes");
    }

    void check_requirements() {
        if (options_.trusted_key) {
            if (v_.signature == "absent") return fail("signature_missing", v_.bytes, "the replay is not signed");
            if (v_.signature == "unchecked") {
                return fail("signature_unchecked", v_.bytes, "this build cannot check signatures (no libsodium)");
            }
            if (!v_.signer_trusted) return fail("untrusted_signer", v_.bytes, "the replay is signed by another key");
        }
        if (options_.expect_hash && *options_.expect_hash != v_.state_hash) {
            fail("expect_mismatch", v_.bytes,
                 "the final state hash is " + hash_hex(v_.state_hash) + ", not the expected " + hash_hex(*options_.expect_hash));
        }
    }

    Scanner scanner_;
    const SceneFor& scene_for_;
    const VerifyOptions& options_;
    const Scene* scene_ = nullptr;
    WorldState state_;
    StepScratch scratch_;
    Verdict v_;
    bool stop_ = false;
    bool located_ = false;
};

}  // namespace

Verdict verify(ByteSource& source, const SceneFor& scene_for, const VerifyOptions& options) {
    return Verification(source, scene_for, options).run();
}

}  // namespace jetrace::replay
