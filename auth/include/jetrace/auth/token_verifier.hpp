// The server's side of connect tokens: checks a presented token against the
// public key, the player's name, the race id and the clock (which the caller
// passes in), and remembers the nonces it admitted until they expire, in a
// table of bounded size (full: refuse rather than grow).
#pragma once

#include "jetrace/auth/connect_token.hpp"

#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace jetrace::auth {

struct VerifierConfig {
    /// The key tokens must be signed with.
    PublicKey public_key{};
    /// Tokens must carry exactly this race id ("" = tokens without one).
    std::string race_id;
    /// Most unexpired admitted nonces remembered; when full, new tokens are
    /// refused until some expire (unit: tokens).
    std::size_t max_nonces = 4096;
};

/// An admitted token's nonce and its token's expiry (unit: s since 1970 UTC).
struct SpentNonce {
    Nonce nonce{};
    std::int64_t expires_unix_s = 0;
    bool operator==(const SpentNonce&) const = default;
};

struct Verdict {
    /// Empty: the token admits the player. Else why not (sent in Refuse).
    std::string refusal;
    ConnectToken token;
    bool ok() const { return refusal.empty(); }
};

class TokenVerifier {
public:
    explicit TokenVerifier(VerifierConfig config);

    /// Checks `bytes` presented by a client calling itself `name` at
    /// `now_unix_s` (unit: s since 1970 UTC). Changes nothing but forgets
    /// expired nonces: call admit() once the client is let in.
    Verdict check(std::span<const std::uint8_t> bytes, std::string_view name, std::int64_t now_unix_s);
    /// Remembers an accepted token's nonce until it expires: it is refused
    /// from now on. The token must have passed check() just before.
    void admit(const ConnectToken& token);

    std::size_t nonces_held() const { return used_.size(); }
    /// Every remembered nonce, in nonce order (to save across restarts).
    std::vector<SpentNonce> spent() const;
    /// Remembers `nonces` as admitted (a restart's saved table). False, and
    /// nothing changed, if a nonce repeats or they exceed max_nonces.
    bool restore(const std::vector<SpentNonce>& nonces, std::string& error);
    const VerifierConfig& config() const { return config_; }

private:
    void forget_expired(std::int64_t now_unix_s);

    VerifierConfig config_;
    std::map<Nonce, std::int64_t> used_;  // nonce -> its token's expiry
};

}  // namespace jetrace::auth
