#include "stun_hash.hpp"

#include <openssl/evp.h>
#include <openssl/hmac.h>
#include <zlib.h>

#include <cassert>
#include <vector>

namespace jetrace::webrtc::detail {

namespace {

constexpr std::uint32_t kFingerprintXor = 0x5354554e;

// The header with its length field replaced.
std::array<std::uint8_t, 20> header_with_length(std::span<const std::uint8_t> prefix, std::uint16_t length_field) {
    assert(prefix.size() >= 20);
    std::array<std::uint8_t, 20> header{};
    for (std::size_t i = 0; i < header.size(); ++i) header[i] = prefix[i];
    header[2] = static_cast<std::uint8_t>(length_field >> 8);
    header[3] = static_cast<std::uint8_t>(length_field);
    return header;
}

}  // namespace

std::optional<std::array<std::uint8_t, 20>> stun_hmac_sha1(std::span<const std::uint8_t> prefix,
                                                           std::uint16_t length_field, std::string_view key) {
    if (key.empty()) return std::nullopt;
    const auto header = header_with_length(prefix, length_field);
    std::vector<std::uint8_t> data(prefix.begin(), prefix.end());
    std::copy(header.begin(), header.end(), data.begin());
    std::array<std::uint8_t, 20> mac{};
    unsigned int mac_size = 0;
    const unsigned char* ok = HMAC(EVP_sha1(), key.data(), static_cast<int>(key.size()), data.data(), data.size(),
                                   mac.data(), &mac_size);
    if (ok == nullptr || mac_size != mac.size()) return std::nullopt;
    return mac;
}

std::uint32_t stun_fingerprint(std::span<const std::uint8_t> prefix, std::uint16_t length_field) {
    const auto header = header_with_length(prefix, length_field);
    uLong crc = crc32(0L, Z_NULL, 0);
    crc = crc32(crc, header.data(), static_cast<uInt>(header.size()));
    const auto rest = prefix.subspan(header.size());
    crc = crc32(crc, rest.data(), static_cast<uInt>(rest.size()));
    return static_cast<std::uint32_t>(crc) ^ kFingerprintXor;
}

}  // namespace jetrace::webrtc::detail
