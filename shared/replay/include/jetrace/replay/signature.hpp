// Streaming Ed25519ph signatures of replay files (libsodium's
// crypto_sign_init/update/final_*), so that signing and checking read a file
// once, in bounded memory. Builds without libsodium (the aarch64 and
// WebAssembly verifiers) have signing_available() false: they neither sign
// nor check signatures, and say so.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>

namespace jetrace::replay {

using SigningKey = std::array<std::uint8_t, 64>;
using VerifyKey = std::array<std::uint8_t, 32>;
using SignatureBytes = std::array<std::uint8_t, 64>;

/// Whether this build can sign and check signatures.
bool signing_available();

/// Accumulates the signed bytes (the domain string first) and signs or checks them.
class SignatureStream {
public:
    SignatureStream();
    ~SignatureStream();
    SignatureStream(const SignatureStream&) = delete;
    SignatureStream& operator=(const SignatureStream&) = delete;

    void update(std::span<const std::uint8_t> bytes);
    /// The signature of everything fed so far with `key` (Ed25519 secret key,
    /// libsodium layout: seed then public key). Ends the stream.
    SignatureBytes sign(const SigningKey& key);
    /// Whether `sig` is `key`'s signature of everything fed. Ends the stream.
    bool verify(const SignatureBytes& sig, const VerifyKey& key);

private:
    struct State;
    std::unique_ptr<State> state_;
};

}  // namespace jetrace::replay
