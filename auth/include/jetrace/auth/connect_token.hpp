// Connect tokens: the ticket a client presents in Hello.connect_token to get
// into a private race (jetrace-server --key-file). A token names the player,
// its expiry, a random nonce and optionally the race it is for, and is signed
// with Ed25519 by whoever holds the secret key (jetrace-token issue); a server
// only needs the public key to check it. Layout and rules: docs/PROTOCOL.md,
// "Connect tokens".
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace jetrace::auth {

/// Format version, the token's first byte.
inline constexpr std::uint8_t kTokenVersion = 1;
/// Longest player name in a token (unit: bytes of UTF-8; = proto::kMaxNameBytes).
inline constexpr std::size_t kMaxTokenNameBytes = 32;
/// Longest race id in a token (unit: bytes of UTF-8).
inline constexpr std::size_t kMaxRaceIdBytes = 64;
inline constexpr std::size_t kNonceBytes = 16;
inline constexpr std::size_t kSignatureBytes = 64;
inline constexpr std::size_t kPublicKeyBytes = 32;
inline constexpr std::size_t kSecretKeyBytes = 64;
/// version, name length, expiry, nonce, race id length, signature (unit: bytes).
inline constexpr std::size_t kMinTokenBytes = 1 + 1 + 8 + kNonceBytes + 1 + kSignatureBytes;
inline constexpr std::size_t kMaxTokenBytes = kMinTokenBytes + kMaxTokenNameBytes + kMaxRaceIdBytes;

using Nonce = std::array<std::uint8_t, kNonceBytes>;
using Signature = std::array<std::uint8_t, kSignatureBytes>;
using PublicKey = std::array<std::uint8_t, kPublicKeyBytes>;
/// libsodium's Ed25519 secret key: the 32-byte seed, then the public key.
using SecretKey = std::array<std::uint8_t, kSecretKeyBytes>;

struct KeyPair {
    PublicKey public_key{};
    SecretKey secret_key{};
};

struct ConnectToken {
    /// The player the token admits: Hello.name must be exactly this.
    std::string name;
    /// The token is refused after this time (unit: s since 1970-01-01 UTC).
    std::int64_t expires_unix_s = 0;
    /// Random; a server admits each nonce once (replay protection).
    Nonce nonce{};
    /// "" or the race this token is for: must equal the server's --race-id.
    std::string race_id;
    Signature signature{};
};

/// Parses untrusted bytes (pure: no keys, clocks or state). Checks the
/// structure only: version, lengths, UTF-8 text without control characters,
/// expiry >= 0, no trailing bytes; the signature is checked by
/// signature_valid(). nullopt with a reason in *error on anything else.
std::optional<ConnectToken> parse_connect_token(std::span<const std::uint8_t> bytes, std::string* error = nullptr);

/// The token's bytes (kMinTokenBytes..kMaxTokenBytes). Asserts the fields
/// are within the rules parse_connect_token() checks.
std::vector<std::uint8_t> serialize(const ConnectToken& token);

/// Fills token.signature by signing its other fields with `key`.
void sign(ConnectToken& token, const SecretKey& key);

/// True if token.signature is `key`'s signature of the token's other fields.
bool signature_valid(const ConnectToken& token, const PublicKey& key);

/// A signed token for `name`, valid until `expires_unix_s`, with a fresh
/// random nonce (what jetrace-token issue prints, as text).
std::vector<std::uint8_t> issue_connect_token(const SecretKey& key, std::string_view name, std::int64_t expires_unix_s,
                                              std::string_view race_id = {});

/// Bytes as unpadded URL-safe base64 (the text form of tokens and keys).
std::string to_text(std::span<const std::uint8_t> bytes);
/// The inverse of to_text() for at most `max_bytes` bytes; surrounding
/// whitespace is ignored. nullopt on anything else.
std::optional<std::vector<std::uint8_t>> from_text(std::string_view text, std::size_t max_bytes);

/// Cryptographically secure random bytes (libsodium). Aborts if libsodium
/// cannot be initialised (no entropy source): nothing sensible can go on.
void random_bytes(std::span<std::uint8_t> out);
KeyPair generate_key_pair();
/// The public half of a secret key.
PublicKey public_key_of(const SecretKey& key);
/// Constant-time equality of two byte strings of the same length.
bool equal_secret(std::span<const std::uint8_t> a, std::span<const std::uint8_t> b);

}  // namespace jetrace::auth
