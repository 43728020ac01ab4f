// A most-significant-bit-first bit writer and a bounds-checked bit reader
// with exp-Golomb codes, for the bit-packed payloads (docs/PROTOCOL.md,
// "Bit conventions"). Internal to jetrace::proto.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace jetrace::proto::bits {

/// Longest exp-Golomb prefix (leading zero bits) the reader accepts: values
/// up to about 2^41 << order, far beyond anything the codec writes.
inline constexpr int kMaxExpGolombZeros = 40;

/// Zigzag mapping of a signed value to an unsigned one: 0, -1, 1, -2, 2 ...
/// -> 0, 1, 2, 3, 4 ... |v| must be below 2^62.
std::uint64_t zigzag(std::int64_t v);
std::int64_t unzigzag(std::uint64_t u);

class BitWriter {
public:
    /// Appends the low `n` bits of `v` (0 <= n <= 64), most significant first.
    void put(std::uint64_t v, int n);
    void put_bit(bool b) { put(b ? 1u : 0u, 1); }
    /// Unsigned exp-Golomb code of order k (v < 2^62, k <= 16).
    void put_ue(std::uint64_t v, int k);
    /// Signed exp-Golomb code of order k: zigzag, then put_ue.
    void put_se(std::int64_t v, int k) { put_ue(zigzag(v), k); }
    /// Bits written so far.
    std::size_t bit_count() const { return bytes_.size() * 8 + static_cast<std::size_t>(pending_bits_); }
    /// The bytes, the last one padded with zero bits. The writer is left empty.
    std::vector<std::uint8_t> finish();

private:
    std::vector<std::uint8_t> bytes_;
    std::uint32_t pending_ = 0;  // low pending_bits_ bits not yet a whole byte
    int pending_bits_ = 0;
};

/// Every read returns false (and leaves `v` unspecified) past the end of the
/// data or on an over-long exp-Golomb prefix; error() then says which.
class BitReader {
public:
    explicit BitReader(std::span<const std::uint8_t> data) : data_(data) {}

    bool get(int n, std::uint64_t& v);
    bool get_bit(bool& b);
    bool get_ue(int k, std::uint64_t& v);
    bool get_se(int k, std::int64_t& v);

    /// Bits consumed so far.
    std::size_t position() const { return pos_; }
    std::size_t bits_left() const { return data_.size() * 8 - pos_; }
    /// True if the rest of the data is fewer than 8 zero bits (the padding of
    /// the last byte).
    bool only_padding_left() const;
    /// Consumes the bits up to the next byte boundary (none if already
    /// there); false if one of them is set.
    bool skip_padding();
    /// The bytes not yet read, from the next byte boundary on.
    std::span<const std::uint8_t> rest_bytes() const { return data_.subspan((pos_ + 7) / 8); }
    const char* error() const { return error_; }

private:
    std::span<const std::uint8_t> data_;
    std::size_t pos_ = 0;
    const char* error_ = "";
};

}  // namespace jetrace::proto::bits
