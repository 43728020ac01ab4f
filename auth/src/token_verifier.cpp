// Checks connect tokens and remembers admitted nonces (bounded).
#include "jetrace/auth/token_verifier.hpp"

#include <cassert>
#include <utility>

namespace jetrace::auth {

TokenVerifier::TokenVerifier(VerifierConfig config) : config_(std::move(config)) {
    assert(config_.max_nonces > 0);
}

void TokenVerifier::forget_expired(std::int64_t now_unix_s) {
    for (auto it = used_.begin(); it != used_.end();) {
        // An expired token is refused for its expiry: its nonce can go.
        it = it->second < now_unix_s ? used_.erase(it) : std::next(it);
    }
}

Verdict TokenVerifier::check(std::span<const std::uint8_t> bytes, std::string_view name, std::int64_t now_unix_s) {
    Verdict v;
    if (bytes.empty()) {
        v.refusal = "private race: a connect token is required";
        return v;
    }
    std::string error;
    auto token = parse_connect_token(bytes, &error);
    if (!token) {
        v.refusal = "connect token malformed: " + error;
        return v;
    }
    v.token = std::move(*token);
    const ConnectToken& t = v.token;
    // Nothing in the token is believed before its signature is.
    if (!signature_valid(t, config_.public_key)) {
        v.refusal = "connect token not signed with this server's key";
    } else if (t.race_id != config_.race_id) {
        v.refusal = "connect token is for race '" + t.race_id + "', this server hosts '" + config_.race_id + "'";
    } else if (t.name != name) {
        v.refusal = "connect token was issued to '" + t.name + "', not to '" + std::string(name) + "'";
    } else if (t.expires_unix_s < now_unix_s) {
        v.refusal = "connect token expired " + std::to_string(now_unix_s - t.expires_unix_s) + " s ago";
    } else if (used_.contains(t.nonce)) {
        v.refusal = "connect token already used";
    } else {
        if (used_.size() >= config_.max_nonces) forget_expired(now_unix_s);
        if (used_.size() >= config_.max_nonces) {
            v.refusal = "too many connect tokens in use (" + std::to_string(config_.max_nonces) +
                        "): try again when some have expired";
        }
    }
    return v;
}

void TokenVerifier::admit(const ConnectToken& token) {
    assert(used_.size() < config_.max_nonces && !used_.contains(token.nonce));
    used_.emplace(token.nonce, token.expires_unix_s);
}

std::vector<SpentNonce> TokenVerifier::spent() const {
    std::vector<SpentNonce> out;
    out.reserve(used_.size());
    for (const auto& [nonce, expiry] : used_) out.push_back({nonce, expiry});
    return out;
}

bool TokenVerifier::restore(const std::vector<SpentNonce>& nonces, std::string& error) {
    std::map<Nonce, std::int64_t> next = used_;
    for (const SpentNonce& n : nonces) {
        if (!next.emplace(n.nonce, n.expires_unix_s).second) {
            error = "a nonce appears twice";
            return false;
        }
    }
    if (next.size() > config_.max_nonces) {
        error = std::to_string(next.size()) + " nonces, more than the " + std::to_string(config_.max_nonces) +
                " the server remembers";
        return false;
    }
    used_ = std::move(next);
    return true;
}

}  // namespace jetrace::auth
