// SignatureStream with libsodium (Ed25519ph).
#include "jetrace/replay/format.hpp"
#include "jetrace/replay/signature.hpp"

#include <sodium.h>

namespace jetrace::replay {

struct SignatureStream::State {
    crypto_sign_state st;
};

bool signing_available() { return sodium_init() >= 0; }

SignatureStream::SignatureStream() : state_(std::make_unique<State>()) {
    crypto_sign_init(&state_->st);
    update({reinterpret_cast<const std::uint8_t*>(kSignatureDomain.data()), kSignatureDomain.size()});
}

SignatureStream::~SignatureStream() = default;

void SignatureStream::update(std::span<const std::uint8_t> bytes) {
    crypto_sign_update(&state_->st, bytes.data(), bytes.size());
}

SignatureBytes SignatureStream::sign(const SigningKey& key) {
    SignatureBytes sig{};
    crypto_sign_final_create(&state_->st, sig.data(), nullptr, key.data());
    return sig;
}

bool SignatureStream::verify(const SignatureBytes& sig, const VerifyKey& key) {
    // libsodium takes a non-const signature pointer; it does not write it.
    SignatureBytes copy = sig;
    return crypto_sign_final_verify(&state_->st, copy.data(), key.data()) == 0;
}

}  // namespace jetrace::replay
