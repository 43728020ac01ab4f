// Reads a replay record by record (untrusted bytes), checking each record's
// length and CRC-32C and the format's grammar, and hands out the decoded
// records one at a time. It does not simulate: the verifier does
// (verify.hpp).
#pragma once

#include "jetrace/replay/format.hpp"
#include "jetrace/replay/signature.hpp"
#include "jetrace/replay/source.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace jetrace::replay {

/// Why reading stopped. The names (problem_name()) are part of the verdict JSON.
enum class Problem : std::uint8_t {
    none,
    io,               ///< the source failed (read error)
    not_a_replay,     ///< bad magic
    old_version,      ///< a format this build does not read
    truncated,        ///< the file ends inside a record
    corrupt,          ///< a record's CRC-32C does not match its bytes
    malformed,        ///< a record is well framed but its contents are wrong
    out_of_sequence,  ///< records in the wrong order, a tick skipped, a checkpoint missing
    incomplete,       ///< the file ends at a record boundary before the trailer
    trailing_bytes,   ///< bytes after the signature record
};
const char* problem_name(Problem p);

struct ScanFailure {
    Problem problem = Problem::none;
    /// Offset of the record (or byte) where it was found.
    std::uint64_t byte_offset = 0;
    /// The world tick reached when it was found.
    std::uint32_t tick = 0;
    std::string message;
};

struct Event {
    RecordKind kind = RecordKind::header;
    std::uint64_t byte_offset = 0;
    Header header;
    TickRecord tick;
    Checkpoint checkpoint;
    WorldState keyframe;
    Trailer trailer;
    Signature signature;
};

class Scanner {
public:
    explicit Scanner(ByteSource& source) : source_(&source) {}

    /// The next record, decoded; false at the end of the file (ok()) or on
    /// a failure (failure()).
    bool next(Event& ev);
    bool ok() const { return failure_.problem == Problem::none; }
    const ScanFailure& failure() const { return failure_; }
    /// The trailer was read.
    bool complete() const { return complete_; }
    /// The world's tick after the last tick record.
    std::uint32_t tick() const { return tick_; }
    std::uint64_t bytes_read() const { return offset_; }
    /// Every byte before the signature record, in order (feeds signing).
    SignatureStream& signed_bytes() { return signed_; }

private:
    enum class State { magic, header, body, after_trailer, after_signature, done };
    bool fail(Problem p, std::uint64_t at, std::string message);
    bool read_magic();
    bool read_record(RecordKind& kind, std::uint64_t& at);
    bool accept(RecordKind kind, std::uint64_t at, Event& ev);
    bool accept_body(RecordKind kind, std::uint64_t at, Event& ev);
    bool at_end(std::uint64_t at);

    ByteSource* source_;
    State state_ = State::magic;
    ScanFailure failure_;
    std::uint64_t offset_ = 0;
    std::vector<std::uint8_t> head_, payload_;
    SignatureStream signed_;
    std::uint32_t initial_tick_ = 0;
    std::uint32_t tick_ = 0;
    std::size_t slots_ = 0;
    std::uint16_t checkpoint_every_ = 1;
    std::uint16_t keyframe_every_ = 0;
    bool checkpoint_due_ = false;
    bool keyframe_due_ = false;
    bool complete_ = false;
};

}  // namespace jetrace::replay
