// SignatureStream in a build without libsodium: no signing, no checking
// (signing_available() is false and callers report signatures unchecked).
#include "jetrace/replay/signature.hpp"

namespace jetrace::replay {

struct SignatureStream::State {};

bool signing_available() { return false; }

SignatureStream::SignatureStream() = default;
SignatureStream::~SignatureStream() = default;
void SignatureStream::update(std::span<const std::uint8_t>) {}
SignatureBytes SignatureStream::sign(const SigningKey&) { return {}; }
bool SignatureStream::verify(const SignatureBytes&, const VerifyKey&) { return false; }

}  // namespace jetrace::replay
