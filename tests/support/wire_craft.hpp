// Building messages by hand, including the ones encode() refuses to build
// (hostile or malformed): flatbuffers helpers and an independent writer of
// the protocol's bit conventions (docs/PROTOCOL.md, "Bit conventions").
#pragma once

#include "jetrace_generated.h"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <vector>

namespace jetrace::test {

namespace fb = flatbuffers;
namespace w = jetrace::wire;

/// Finishes a hand-built message, with the builder's padding.
template <typename T>
std::vector<std::uint8_t> finish(fb::FlatBufferBuilder& b, fb::Offset<T> root, const char* id) {
    b.Finish(root, id);
    return {b.GetBufferPointer(), b.GetBufferPointer() + b.GetSize()};
}

/// Hello and Refuse: a hand-built Envelope.
inline std::vector<std::uint8_t> envelope(fb::FlatBufferBuilder& b, w::Handshake type, fb::Offset<void> body) {
    w::FinishEnvelopeBuffer(b, w::CreateEnvelope(b, type, body));
    return {b.GetBufferPointer(), b.GetBufferPointer() + b.GetSize()};
}

/// Writes bits most significant first: u(n), ue(k) (exp-Golomb), se(k).
struct Bits {
    std::vector<bool> v;
    Bits& u(std::uint64_t x, int n) {
        for (int i = n - 1; i >= 0; --i) v.push_back(((x >> i) & 1u) != 0);
        return *this;
    }
    Bits& ue(std::uint64_t x, int k) {
        const std::uint64_t y = x + (std::uint64_t{1} << k);
        const int width = static_cast<int>(std::bit_width(y));
        return u(0, width - 1 - k).u(y, width);
    }
    Bits& se(std::int64_t x, int k) {
        return ue(x >= 0 ? static_cast<std::uint64_t>(x) * 2 : static_cast<std::uint64_t>(-x) * 2 - 1, k);
    }
    std::vector<std::uint8_t> bytes(std::uint8_t padding = 0) const {
        std::vector<std::uint8_t> out((v.size() + 7) / 8, 0);
        for (std::size_t i = 0; i < v.size(); ++i)
            if (v[i]) out[i / 8] |= static_cast<std::uint8_t>(0x80u >> (i % 8));
        if (v.size() % 8 != 0) out.back() |= static_cast<std::uint8_t>(padding & ((1u << (8 - v.size() % 8)) - 1));
        return out;
    }
};

/// A packed message (InputBatch, Snapshot): 4 zero bytes, the identifier, the payload.
inline std::vector<std::uint8_t> packed_message(const char* id, const std::vector<std::uint8_t>& payload) {
    std::vector<std::uint8_t> out(8 + payload.size(), 0);
    for (std::size_t i = 0; i < 4; ++i) out[4 + i] = static_cast<std::uint8_t>(id[i]);
    std::copy(payload.begin(), payload.end(), out.begin() + 8);
    return out;
}

/// An InputBatch message around a hand-made payload.
inline std::vector<std::uint8_t> input_batch(const std::vector<std::uint8_t>& payload) {
    return packed_message("JINP", payload);
}

/// A Snapshot message around a hand-made payload.
inline std::vector<std::uint8_t> snapshot_message(const std::vector<std::uint8_t>& payload) {
    return packed_message("JSNP", payload);
}

}  // namespace jetrace::test
