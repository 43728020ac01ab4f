// Connect tokens: layout, Ed25519 signatures (libsodium), text form.
// Layout (docs/PROTOCOL.md, "Connect tokens"), integers little-endian:
//   version u8 (1) | name length u8 (0..32) | name | expires_unix_s i64 (>= 0)
//   | nonce (16) | race id length u8 (0..64) | race id | signature (64)
// The signature covers kDomain followed by every byte before it.
#include "jetrace/auth/connect_token.hpp"

#include "jetrace/proto/messages.hpp"

#include <sodium.h>

#include <cassert>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace jetrace::auth {

namespace {

static_assert(kPublicKeyBytes == crypto_sign_PUBLICKEYBYTES);
static_assert(kSecretKeyBytes == crypto_sign_SECRETKEYBYTES);
static_assert(kSignatureBytes == crypto_sign_BYTES);
static_assert(kMaxTokenNameBytes == proto::kMaxNameBytes);
static_assert(kMaxTokenBytes <= proto::kMaxConnectTokenBytes);

/// Prefixed to the signed bytes so that a signature made for anything else
/// with the same key can never pass as a token.
constexpr std::string_view kDomain = "jetrace connect token\n";

void init_sodium() {
    static const bool ok = sodium_init() >= 0;
    if (!ok) {
        std::fputs("jetrace: libsodium cannot be initialised (no entropy source?)\n", stderr);
        std::abort();
    }
}

std::nullopt_t fail(std::string* error, const char* what) {
    if (error) *error = what;
    return std::nullopt;
}

/// Domain, then the token's bytes without the signature.
std::vector<std::uint8_t> signed_message(const ConnectToken& t) {
    const std::vector<std::uint8_t> token = serialize(t);
    assert(token.size() >= kSignatureBytes);  // serialize() always writes the signature last
    const std::size_t signed_bytes = token.size() - kSignatureBytes;
    std::vector<std::uint8_t> bytes(kDomain.size() + signed_bytes);
    std::memcpy(bytes.data(), kDomain.data(), kDomain.size());
    std::memcpy(bytes.data() + kDomain.size(), token.data(), signed_bytes);
    return bytes;
}

}  // namespace

std::optional<ConnectToken> parse_connect_token(std::span<const std::uint8_t> bytes, std::string* error) {
    ConnectToken t;
    std::size_t at = 0;
    const auto take = [&](std::size_t n) -> const std::uint8_t* {
        if (bytes.size() - at < n) return nullptr;
        const std::uint8_t* p = bytes.data() + at;
        at += n;
        return p;
    };
    if (bytes.size() < kMinTokenBytes) return fail(error, "too short");
    if (bytes.size() > kMaxTokenBytes) return fail(error, "too long");
    if (*take(1) != kTokenVersion) return fail(error, "unknown version");
    const std::size_t name_len = *take(1);
    if (name_len > kMaxTokenNameBytes) return fail(error, "name too long");
    const std::uint8_t* name = take(name_len);
    if (!name) return fail(error, "truncated in the name");
    t.name.assign(reinterpret_cast<const char*>(name), name_len);
    if (!proto::valid_text(t.name)) return fail(error, "name is not UTF-8 text");
    const std::uint8_t* expiry = take(8);
    if (!expiry) return fail(error, "truncated in the expiry");
    std::uint64_t e = 0;
    for (int i = 7; i >= 0; --i) e = (e << 8) | expiry[i];
    if (e > static_cast<std::uint64_t>(INT64_MAX)) return fail(error, "expiry out of range");
    t.expires_unix_s = static_cast<std::int64_t>(e);
    const std::uint8_t* nonce = take(kNonceBytes);
    if (!nonce) return fail(error, "truncated in the nonce");
    std::memcpy(t.nonce.data(), nonce, kNonceBytes);
    const std::uint8_t* race_len = take(1);
    if (!race_len) return fail(error, "truncated before the race id");
    if (*race_len > kMaxRaceIdBytes) return fail(error, "race id too long");
    const std::uint8_t* race = take(*race_len);
    if (!race) return fail(error, "truncated in the race id");
    t.race_id.assign(reinterpret_cast<const char*>(race), *race_len);
    if (!proto::valid_text(t.race_id)) return fail(error, "race id is not UTF-8 text");
    const std::uint8_t* sig = take(kSignatureBytes);
    if (!sig) return fail(error, "truncated in the signature");
    std::memcpy(t.signature.data(), sig, kSignatureBytes);
    if (at != bytes.size()) return fail(error, "trailing bytes after the signature");
    return t;
}

std::vector<std::uint8_t> serialize(const ConnectToken& t) {
    assert(t.name.size() <= kMaxTokenNameBytes && proto::valid_text(t.name));
    assert(t.race_id.size() <= kMaxRaceIdBytes && proto::valid_text(t.race_id));
    assert(t.expires_unix_s >= 0);
    std::vector<std::uint8_t> out;
    out.reserve(kMaxTokenBytes);
    out.push_back(kTokenVersion);
    out.push_back(static_cast<std::uint8_t>(t.name.size()));
    out.insert(out.end(), t.name.begin(), t.name.end());
    const auto e = static_cast<std::uint64_t>(t.expires_unix_s);
    for (int i = 0; i < 8; ++i) out.push_back(static_cast<std::uint8_t>(e >> (8 * i)));
    out.insert(out.end(), t.nonce.begin(), t.nonce.end());
    out.push_back(static_cast<std::uint8_t>(t.race_id.size()));
    out.insert(out.end(), t.race_id.begin(), t.race_id.end());
    out.insert(out.end(), t.signature.begin(), t.signature.end());
    return out;
}

void sign(ConnectToken& token, const SecretKey& key) {
    init_sodium();
    const std::vector<std::uint8_t> msg = signed_message(token);
    crypto_sign_detached(token.signature.data(), nullptr, msg.data(), msg.size(), key.data());
}

bool signature_valid(const ConnectToken& token, const PublicKey& key) {
    init_sodium();
    const std::vector<std::uint8_t> msg = signed_message(token);
    return crypto_sign_verify_detached(token.signature.data(), msg.data(), msg.size(), key.data()) == 0;
}

std::vector<std::uint8_t> issue_connect_token(const SecretKey& key, std::string_view name, std::int64_t expires_unix_s,
                                              std::string_view race_id) {
    ConnectToken t;
    t.name = name;
    t.expires_unix_s = expires_unix_s;
    t.race_id = race_id;
    random_bytes(t.nonce);
    sign(t, key);
    return serialize(t);
}

std::string to_text(std::span<const std::uint8_t> bytes) {
    init_sodium();
    constexpr int kVariant = sodium_base64_VARIANT_URLSAFE_NO_PADDING;
    std::string out(sodium_base64_ENCODED_LEN(bytes.size(), kVariant), '\0');
    sodium_bin2base64(out.data(), out.size(), bytes.data(), bytes.size(), kVariant);
    out.resize(std::strlen(out.c_str()));
    return out;
}

std::optional<std::vector<std::uint8_t>> from_text(std::string_view text, std::size_t max_bytes) {
    init_sodium();
    while (!text.empty() && (text.front() == ' ' || text.front() == '\t' || text.front() == '\n' || text.front() == '\r'))
        text.remove_prefix(1);
    while (!text.empty() && (text.back() == ' ' || text.back() == '\t' || text.back() == '\n' || text.back() == '\r'))
        text.remove_suffix(1);
    // Four characters carry three bytes: anything longer cannot fit.
    if (text.empty() || text.size() > (max_bytes * 4 + 2) / 3) return std::nullopt;
    std::vector<std::uint8_t> out(max_bytes);
    std::size_t len = 0;
    const char* end = nullptr;
    if (sodium_base642bin(out.data(), out.size(), text.data(), text.size(), nullptr, &len, &end,
                          sodium_base64_VARIANT_URLSAFE_NO_PADDING) != 0 ||
        end != text.data() + text.size()) {
        return std::nullopt;
    }
    out.resize(len);
    return out;
}

void random_bytes(std::span<std::uint8_t> out) {
    init_sodium();
    randombytes_buf(out.data(), out.size());
}

KeyPair generate_key_pair() {
    init_sodium();
    KeyPair k;
    crypto_sign_keypair(k.public_key.data(), k.secret_key.data());
    return k;
}

PublicKey public_key_of(const SecretKey& key) {
    init_sodium();
    PublicKey pk{};
    crypto_sign_ed25519_sk_to_pk(pk.data(), key.data());
    return pk;
}

bool equal_secret(std::span<const std::uint8_t> a, std::span<const std::uint8_t> b) {
    init_sodium();
    return a.size() == b.size() && sodium_memcmp(a.data(), b.data(), a.size()) == 0;
}

}  // namespace jetrace::auth
