// Verifies a replay while re-simulating it with this build's core: every
// record's CRC-32C and the grammar (scanner.hpp), every checkpoint's state
// and car hashes, every keyframe bit for bit, the trailer's final tick,
// state hash and results, and the signature. Reads the file once, in
// bounded memory. A checkpoint that differs is followed to the next
// keyframe, whose fields are compared by name (the desync finder's detail).
#pragma once

#include "jetrace/replay/fields.hpp"
#include "jetrace/replay/scanner.hpp"

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace jetrace::replay {

/// The scene a header names, or null with a reason (track unknown, ...).
using SceneFor = std::function<const Scene*(const Header& header, std::string& error)>;

struct VerifyOptions {
    /// The signature must be by this key (and present).
    std::optional<VerifyKey> trusted_key;
    /// The final state hash must be this.
    std::optional<std::uint64_t> expect_hash;
    /// Differing fields reported at most (unit: fields).
    std::size_t max_fields = 16;
};

struct Verdict {
    bool ok = false;
    std::string track;
    std::uint32_t race_number = 0;
    std::uint32_t initial_tick = 0;
    /// The world's tick when reading stopped.
    std::uint32_t final_tick = 0;
    /// state_hash() of the re-simulated world when reading stopped.
    std::uint64_t state_hash = 0;
    std::uint32_t checkpoints = 0;
    std::uint32_t keyframes = 0;
    /// The last checkpoint that matched (none: no checkpoint matched).
    std::optional<std::uint32_t> last_good_checkpoint;
    /// The trailer was read; then end_reason is set.
    bool complete = false;
    std::string end_reason;
    std::vector<ResultEntry> results;
    /// "valid", "invalid", "absent", or "unchecked" (a build without libsodium).
    std::string signature = "absent";
    /// The signing key as 64 hex digits, when signed.
    std::string signer;
    bool signer_trusted = false;
    std::uint64_t bytes = 0;

    /// The first failure: "" when ok, else a scanner problem_name() or one
    /// of track, physics, checkpoint_mismatch, keyframe_mismatch,
    /// final_hash_mismatch, results_mismatch, signature_invalid,
    /// signature_missing, signature_unchecked, untrusted_signer, expect_mismatch.
    std::string problem;
    std::uint64_t byte_offset = 0;
    std::uint32_t tick = 0;
    std::string message;
    /// Slots whose car hash differs at the failing checkpoint.
    std::vector<int> cars;
    /// Recorded (a) against re-simulated (b), at fields_tick.
    std::optional<std::uint32_t> fields_tick;
    std::vector<FieldDifference> fields;
};

Verdict verify(ByteSource& source, const SceneFor& scene_for, const VerifyOptions& options = {});

/// The verdict as one line of JSON.
std::string to_json(const Verdict& v);

/// The cars whose hashes differ between two checkpoints of the same tick.
std::vector<int> differing_cars(const Checkpoint& a, const Checkpoint& b);

/// 64 lowercase hex digits.
std::string hex(std::span<const std::uint8_t> bytes);

}  // namespace jetrace::replay
