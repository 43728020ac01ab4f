#include "jetrace/replay/writer.hpp"

#include "jetrace/core/state_bytes.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <unistd.h>

namespace jetrace::replay {

namespace {
constexpr int kFlushEveryTicks = 120;
}

Writer::~Writer() { abandon(); }

bool Writer::open(const std::string& path, const Header& header, const std::optional<SigningKey>& sign_key) {
    abandon();
    error_.clear();
    written_ = 0;
    path_ = path;
    if (sign_key && !signing_available()) {
        error_ = "this build cannot sign replays (built without libsodium)";
        return false;
    }
    file_ = std::fopen(path.c_str(), "wb");
    if (!file_) {
        error_ = "cannot create replay file '" + path + "': " + std::strerror(errno);
        return false;
    }
    sign_key_ = sign_key;
    signed_.reset();
    if (sign_key_) signed_.emplace();
    initial_tick_ = header.initial.tick;
    checkpoint_every_ = header.checkpoint_every;
    keyframe_every_ = header.keyframe_every;
    buffer_.assign(kMagic.begin(), kMagic.end());
    if (signed_) signed_->update(kMagic);
    payload_.clear();
    encode(header, payload_);
    put(RecordKind::header);
    flush();
    return error_.empty();
}

void Writer::put(RecordKind kind) {
    const std::size_t start = buffer_.size();
    frame(kind, payload_, buffer_);
    if (signed_ && kind != RecordKind::signature) signed_->update(std::span(buffer_).subspan(start));
    payload_.clear();
}

void Writer::record_tick(std::uint32_t tick, std::span<const std::uint8_t> removed, std::span<const Input> inputs) {
    if (!file_) return;
    encode_tick(tick, removed, inputs, payload_);
    put(RecordKind::tick);
}

void Writer::stepped(const WorldState& state) {
    if (!file_) return;
    const std::uint32_t since = state.tick - initial_tick_;
    if (since % checkpoint_every_ == 0) {
        encode(checkpoint_of(state), payload_);
        put(RecordKind::checkpoint);
        if (keyframe_every_ != 0 && since % keyframe_every_ == 0) {
            write_state(state, payload_);
            put(RecordKind::keyframe);
        }
    }
    if (++since_flush_ >= kFlushEveryTicks) flush();
}

void Writer::flush() {
    since_flush_ = 0;
    if (!file_ || buffer_.empty()) return;
    const std::size_t n = std::fwrite(buffer_.data(), 1, buffer_.size(), file_);
    const bool flushed = n == buffer_.size() && std::fflush(file_) == 0;
    if (!flushed && error_.empty()) {
        error_ = "cannot write replay file '" + path_ + "': " + std::strerror(errno) + " (the replay is cut at byte " +
                 std::to_string(written_ + n) + ")";
    }
    written_ += n;
    buffer_.clear();
    if (!flushed) close();
}

bool Writer::finish(const Trailer& trailer) {
    if (!file_) return error_.empty();
    encode(trailer, payload_);
    put(RecordKind::trailer);
    if (sign_key_) {
        Signature s;
        std::copy(sign_key_->begin() + 32, sign_key_->end(), s.public_key.begin());
        s.signature = signed_->sign(*sign_key_);
        encode(s, payload_);
        put(RecordKind::signature);
    }
    flush();
    if (file_ && ::fsync(::fileno(file_)) != 0 && error_.empty()) {
        error_ = "cannot sync replay file '" + path_ + "' to disk: " + std::strerror(errno);
    }
    close();
    return error_.empty();
}

void Writer::abandon() {
    flush();
    close();
}

void Writer::close() {
    if (!file_) return;
    if (std::fclose(file_) != 0 && error_.empty()) {
        error_ = "cannot close replay file '" + path_ + "': " + std::strerror(errno);
    }
    file_ = nullptr;
}

}  // namespace jetrace::replay
