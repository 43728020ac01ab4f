#include "jetrace/replay/scanner.hpp"

#include "jetrace/core/crc32c.hpp"

#include <algorithm>
#include <cstring>

namespace jetrace::replay {

const char* problem_name(Problem p) {
    switch (p) {
        case Problem::none: return "none";
        case Problem::io: return "io";
        case Problem::not_a_replay: return "not_a_replay";
        case Problem::old_version: return "old_version";
        case Problem::truncated: return "truncated";
        case Problem::corrupt: return "corrupt";
        case Problem::malformed: return "malformed";
        case Problem::out_of_sequence: return "out_of_sequence";
        case Problem::incomplete: return "incomplete";
        case Problem::trailing_bytes: return "trailing_bytes";
    }
    return "unknown";
}

namespace {
std::uint32_t le32(const std::uint8_t* p) {
    return std::uint32_t{p[0]} | std::uint32_t{p[1]} << 8 | std::uint32_t{p[2]} << 16 | std::uint32_t{p[3]} << 24;
}
}  // namespace

bool Scanner::fail(Problem p, std::uint64_t at, std::string message) {
    failure_ = ScanFailure{p, at, tick_, std::move(message)};
    state_ = State::done;
    return false;
}

bool Scanner::read_magic() {
    std::array<std::uint8_t, kMagic.size()> m{};
    const std::size_t n = source_->read(m.data(), m.size());
    offset_ = n;
    if (n < m.size() && !source_->error().empty()) return fail(Problem::io, 0, source_->error());
    if (n == m.size() && std::equal(m.begin(), m.end() - 1, kMagic.begin()) && m.back() != kMagic.back()) {
        return fail(Problem::old_version, 7,
                    std::string("replay format version ") + static_cast<char>(m.back()) +
                        " is not read by this build, which reads version 2 (checksummed records and a trailer); "
                        "record the race again");
    }
    if (n < m.size() || m != kMagic) return fail(Problem::not_a_replay, 0, "not a jetrace replay (bad magic)");
    signed_.update(m);
    state_ = State::header;
    return true;
}

bool Scanner::read_record(RecordKind& kind, std::uint64_t& at) {
    at = offset_;
    head_.resize(kRecordHeadBytes);
    const std::size_t h = source_->read(head_.data(), head_.size());
    offset_ += h;
    if (h < head_.size() && !source_->error().empty()) return fail(Problem::io, at, source_->error());
    if (h == 0) return at_end(at);
    if (h < head_.size()) return fail(Problem::truncated, at, "the file ends inside the record at byte " + std::to_string(at));
    const std::uint32_t length = le32(head_.data() + 1);
    if (length > kMaxPayloadBytes) {
        return fail(Problem::corrupt, at,
                    "the record at byte " + std::to_string(at) + " claims " + std::to_string(length) +
                        " bytes, more than any record has");
    }
    payload_.resize(std::size_t{length} + kRecordTailBytes);
    const std::size_t p = source_->read(payload_.data(), payload_.size());
    offset_ += p;
    if (p < payload_.size() && !source_->error().empty()) return fail(Problem::io, at, source_->error());
    if (p < payload_.size()) {
        return fail(Problem::truncated, at,
                    "the file ends inside the record at byte " + std::to_string(at) + " (" +
                        std::to_string(p) + " of its " + std::to_string(payload_.size()) + " bytes are there)");
    }
    const std::uint32_t crc = crc32c(std::span(payload_).first(length), crc32c(head_));
    if (crc != le32(payload_.data() + length)) {
        return fail(Problem::corrupt, at, "the record at byte " + std::to_string(at) + " fails its CRC-32C");
    }
    kind = static_cast<RecordKind>(head_[0]);
    if (kind != RecordKind::signature) {
        signed_.update(head_);
        signed_.update(payload_);
    }
    payload_.resize(length);
    return true;
}

bool Scanner::at_end(std::uint64_t at) {
    if (state_ == State::after_trailer || state_ == State::after_signature) {
        state_ = State::done;
        return false;
    }
    if (state_ == State::header) return fail(Problem::incomplete, at, "the file has no header record");
    return fail(Problem::incomplete, at,
                "the replay has no trailer: the recording stops after tick " + std::to_string(tick_) +
                    " (the recorder was killed or ran out of disk), so it is not a complete race");
}

bool Scanner::next(Event& ev) {
    if (state_ == State::done) return false;
    if (state_ == State::magic && !read_magic()) return false;
    RecordKind kind{};
    std::uint64_t at = 0;
    if (!read_record(kind, at)) return false;
    ev.kind = kind;
    ev.byte_offset = at;
    return accept(kind, at, ev);
}

bool Scanner::accept(RecordKind kind, std::uint64_t at, Event& ev) {
    std::string error;
    const std::string where = " at byte " + std::to_string(at);
    switch (state_) {
        case State::header:
            if (kind != RecordKind::header) return fail(Problem::out_of_sequence, at, "the first record is not a header");
            if (!decode(payload_, ev.header, error)) return fail(Problem::malformed, at, error + where);
            initial_tick_ = tick_ = ev.header.initial.tick;
            slots_ = ev.header.initial.cars.size();
            checkpoint_every_ = ev.header.checkpoint_every;
            keyframe_every_ = ev.header.keyframe_every;
            state_ = State::body;
            return true;
        case State::body: return accept_body(kind, at, ev);
        case State::after_trailer:
            if (kind != RecordKind::signature) return fail(Problem::out_of_sequence, at, "a record after the trailer" + where);
            if (!decode(payload_, ev.signature, error)) return fail(Problem::malformed, at, error + where);
            state_ = State::after_signature;
            return true;
        default: return fail(Problem::trailing_bytes, at, "bytes after the signature" + where);
    }
}

bool Scanner::accept_body(RecordKind kind, std::uint64_t at, Event& ev) {
    std::string error;
    const std::string where = " at byte " + std::to_string(at);
    const bool due = checkpoint_due_ || keyframe_due_;
    const char* missing = checkpoint_due_ ? "checkpoint" : "keyframe";
    switch (kind) {
        case RecordKind::tick:
            if (due) return fail(Problem::out_of_sequence, at, std::string("the ") + missing + " of tick " + std::to_string(tick_) + " is missing" + where);
            if (!decode(payload_, slots_, ev.tick, error)) return fail(Problem::malformed, at, error + where);
            if (ev.tick.tick != tick_) {
                return fail(Problem::out_of_sequence, at,
                            "tick record " + std::to_string(ev.tick.tick) + " where tick " + std::to_string(tick_) + " was due" + where);
            }
            ++tick_;
            checkpoint_due_ = (tick_ - initial_tick_) % checkpoint_every_ == 0;
            return true;
        case RecordKind::checkpoint:
            if (!checkpoint_due_) return fail(Problem::out_of_sequence, at, "a checkpoint where none is due" + where);
            if (!decode(payload_, ev.checkpoint, error)) return fail(Problem::malformed, at, error + where);
            if (ev.checkpoint.tick != tick_ || ev.checkpoint.car_hashes.size() != slots_) {
                return fail(Problem::malformed, at, "the checkpoint names the wrong tick or slot count" + where);
            }
            checkpoint_due_ = false;
            keyframe_due_ = keyframe_every_ != 0 && (tick_ - initial_tick_) % keyframe_every_ == 0;
            return true;
        case RecordKind::keyframe:
            if (!keyframe_due_) return fail(Problem::out_of_sequence, at, "a keyframe where none is due" + where);
            if (!decode_keyframe(payload_, ev.keyframe, error)) return fail(Problem::malformed, at, error + where);
            if (ev.keyframe.tick != tick_ || ev.keyframe.cars.size() != slots_) {
                return fail(Problem::malformed, at, "the keyframe names the wrong tick or slot count" + where);
            }
            keyframe_due_ = false;
            return true;
        case RecordKind::trailer:
            if (due) return fail(Problem::out_of_sequence, at, std::string("the ") + missing + " of tick " + std::to_string(tick_) + " is missing" + where);
            if (!decode(payload_, slots_, ev.trailer, error)) return fail(Problem::malformed, at, error + where);
            if (ev.trailer.final_tick != tick_) {
                return fail(Problem::malformed, at,
                            "the trailer says the race ended at tick " + std::to_string(ev.trailer.final_tick) +
                                " but the records end at tick " + std::to_string(tick_) + where);
            }
            state_ = State::after_trailer;
            complete_ = true;
            return true;
        case RecordKind::header:
        case RecordKind::signature:
            return fail(Problem::out_of_sequence, at, "a header or signature record inside the race" + where);
    }
    return fail(Problem::malformed, at, "unknown record kind " + std::to_string(static_cast<int>(kind)) + where);
}

}  // namespace jetrace::replay
