// parse_connect_token() on untrusted bytes (what a server reads from
// Hello.connect_token) and from_text() on untrusted text (what jetrace-bot
// and jetrace-token read from a command line or a file). Invariants: an
// accepted token serialises back to exactly the input bytes and parses to
// the same fields; checking its signature against a key never fails
// unexpectedly (an unsigned fuzz input must not verify); text that decodes
// re-encodes to text that decodes to the same bytes.
#include "fuzz_check.hpp"
#include "jetrace/auth/connect_token.hpp"

#include <algorithm>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    namespace ja = jetrace::auth;
    std::string error;
    const auto token = ja::parse_connect_token(jetrace::fuzz::bytes(data, size), &error);
    if (!token) {
        JETRACE_FUZZ_CHECK(!error.empty());
    } else {
        const std::vector<std::uint8_t> again = ja::serialize(*token);
        JETRACE_FUZZ_CHECK(again.size() == size && std::equal(again.begin(), again.end(), data));
        const auto reparsed = ja::parse_connect_token(again);
        JETRACE_FUZZ_CHECK(reparsed && reparsed->name == token->name && reparsed->race_id == token->race_id &&
                           reparsed->expires_unix_s == token->expires_unix_s && reparsed->nonce == token->nonce);
        // A fixed key that signed nothing here: a forged signature must fail.
        const ja::PublicKey key{};
        JETRACE_FUZZ_CHECK(!ja::signature_valid(*token, key));
    }
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    if (const auto decoded = ja::from_text(text, ja::kMaxTokenBytes)) {
        const auto round = ja::from_text(ja::to_text(*decoded), ja::kMaxTokenBytes);
        JETRACE_FUZZ_CHECK(round && *round == *decoded);
    }
    return 0;
}
