#include "bitstream.hpp"

#include <bit>
#include <cassert>

namespace jetrace::proto::bits {

std::uint64_t zigzag(std::int64_t v) {
    assert(v > -(std::int64_t{1} << 62) && v < (std::int64_t{1} << 62));
    return v >= 0 ? static_cast<std::uint64_t>(v) << 1 : (static_cast<std::uint64_t>(-(v + 1)) << 1) | 1u;
}

std::int64_t unzigzag(std::uint64_t u) {
    const auto half = static_cast<std::int64_t>(u >> 1);  // u < 2^64: half < 2^63
    return (u & 1u) != 0 ? -half - 1 : half;
}

void BitWriter::put(std::uint64_t v, int n) {
    assert(n >= 0 && n <= 64);
    if (n < 64) v &= (std::uint64_t{1} << n) - 1;
    // Feed at most 8 bits at a time into the pending byte.
    while (n > 0) {
        const int take = n < 8 - pending_bits_ ? n : 8 - pending_bits_;
        n -= take;
        const auto chunk = static_cast<std::uint32_t>((v >> n) & ((1u << take) - 1));
        pending_ = (pending_ << take) | chunk;
        pending_bits_ += take;
        if (pending_bits_ == 8) {
            bytes_.push_back(static_cast<std::uint8_t>(pending_));
            pending_ = 0;
            pending_bits_ = 0;
        }
    }
}

void BitWriter::put_ue(std::uint64_t v, int k) {
    assert(k >= 0 && k <= 16 && v < (std::uint64_t{1} << 62));
    const std::uint64_t x = v + (std::uint64_t{1} << k);
    const auto width = static_cast<int>(std::bit_width(x));  // >= k + 1
    put(0, width - 1 - k);
    put(x, width);
}

std::vector<std::uint8_t> BitWriter::finish() {
    if (pending_bits_ > 0) put(0, 8 - pending_bits_);
    std::vector<std::uint8_t> out;
    out.swap(bytes_);
    return out;
}

bool BitReader::get(int n, std::uint64_t& v) {
    assert(n >= 0 && n <= 64);
    if (static_cast<std::size_t>(n) > bits_left()) {
        error_ = "truncated";
        return false;
    }
    v = 0;
    while (n > 0) {
        const std::size_t byte = pos_ >> 3;
        const int offset = static_cast<int>(pos_ & 7);
        const int avail = 8 - offset;
        const int take = n < avail ? n : avail;
        const unsigned bits = (static_cast<unsigned>(data_[byte]) >> (avail - take)) & ((1u << take) - 1);
        v = (v << take) | bits;
        pos_ += static_cast<std::size_t>(take);
        n -= take;
    }
    return true;
}

bool BitReader::get_bit(bool& b) {
    std::uint64_t v = 0;
    if (!get(1, v)) return false;
    b = v != 0;
    return true;
}

bool BitReader::get_ue(int k, std::uint64_t& v) {
    int zeros = 0;
    for (;;) {
        bool b = false;
        if (!get_bit(b)) return false;
        if (b) break;
        if (++zeros > kMaxExpGolombZeros) {
            error_ = "exp-Golomb prefix too long";
            return false;
        }
    }
    std::uint64_t rest = 0;
    if (!get(zeros + k, rest)) return false;
    const std::uint64_t x = (std::uint64_t{1} << (zeros + k)) | rest;
    v = x - (std::uint64_t{1} << k);
    return true;
}

bool BitReader::get_se(int k, std::int64_t& v) {
    std::uint64_t u = 0;
    if (!get_ue(k, u)) return false;
    v = unzigzag(u);
    return true;
}

bool BitReader::only_padding_left() const {
    const std::size_t left = bits_left();
    if (left >= 8) return false;
    if (left == 0) return true;
    const unsigned mask = (1u << left) - 1;
    return (data_.back() & mask) == 0;
}

bool BitReader::skip_padding() {
    const int n = static_cast<int>((8 - (pos_ & 7)) & 7);
    std::uint64_t v = 0;
    if (!get(n, v)) return false;  // cannot happen: the byte is there
    if (v != 0) {
        error_ = "non-zero padding";
        return false;
    }
    return true;
}

}  // namespace jetrace::proto::bits
