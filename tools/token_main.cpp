// jetrace-token: keys and connect tokens for private races.
//   jetrace-token keygen --out FILE          FILE (secret, mode 0600) and FILE.pub (for jetrace-server --key-file)
//   jetrace-token issue --key-file FILE --name NAME --valid-for S [--race-id ID]
//   jetrace-token inspect TOKEN [--key-file FILE]
// docs/PROTOCOL.md, "Connect tokens".
#include "jetrace/auth/connect_token.hpp"
#include "jetrace/auth/key_file.hpp"
#include "jetrace/proto/messages.hpp"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>

namespace {

std::int64_t unix_now_s() {
    return std::chrono::duration_cast<std::chrono::seconds>(std::chrono::system_clock::now().time_since_epoch())
        .count();
}

int fail(const std::string& message) {
    std::fprintf(stderr, "jetrace-token: %s\n", message.c_str());
    return 2;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"jetrace-token: keys and connect tokens for private jetrace races"};
    app.require_subcommand(1);

    auto* keygen = app.add_subcommand("keygen", "make an Ed25519 key pair: FILE (secret) and FILE.pub (public)");
    std::string out_path;
    bool force = false;
    keygen->add_option("--out", out_path, "secret key file to write (the public key goes to FILE.pub)")->required();
    keygen->add_flag("--force", force, "overwrite existing files");

    auto* issue = app.add_subcommand("issue", "print a signed connect token (base64url) for one player");
    std::string key_path;
    std::string name;
    std::int64_t valid_for_s = 0;
    std::string race_id;
    issue->add_option("--key-file", key_path, "secret key file (jetrace-token keygen)")->required();
    issue->add_option("--name", name, "the player's name (its Hello must use exactly this)")->required();
    issue->add_option("--valid-for", valid_for_s, "seconds from now until the token expires (1..2592000)")
        ->required()
        ->check(CLI::Range(std::int64_t{1}, std::int64_t{30 * 86400}));
    issue->add_option("--race-id", race_id, "the race the token is for (the server's --race-id)");

    auto* inspect = app.add_subcommand("inspect", "print a token's fields as JSON (and check it with --key-file)");
    std::string token_text;
    std::string inspect_key;
    inspect->add_option("token", token_text, "the token (base64url)")->required();
    inspect->add_option("--key-file", inspect_key, "public or secret key file to check the signature with");

    CLI11_PARSE(app, argc, argv);
    std::string error;

    if (*keygen) {
        if (!jetrace::auth::write_key_files(out_path, jetrace::auth::generate_key_pair(), force, error)) return fail(error);
        std::printf("secret key: %s (keep it private: it issues tokens)\npublic key: %s.pub (jetrace-server --key-file)\n",
                    out_path.c_str(), out_path.c_str());
        return 0;
    }
    if (*issue) {
        if (name.size() > jetrace::auth::kMaxTokenNameBytes || !jetrace::proto::valid_text(name))
            return fail("--name must be at most 32 bytes of UTF-8 text without control characters");
        if (race_id.size() > jetrace::auth::kMaxRaceIdBytes || !jetrace::proto::valid_text(race_id))
            return fail("--race-id must be at most 64 bytes of UTF-8 text without control characters");
        jetrace::auth::LoadedKey key;
        if (!jetrace::auth::load_key_file(key_path, key, error)) return fail(error);
        if (!key.has_secret) return fail("'" + key_path + "' is a public key: issuing needs the secret key file");
        const auto token = jetrace::auth::issue_connect_token(key.secret, name, unix_now_s() + valid_for_s, race_id);
        std::printf("%s\n", jetrace::auth::to_text(token).c_str());
        return 0;
    }
    // inspect
    const auto bytes = jetrace::auth::from_text(token_text, jetrace::auth::kMaxTokenBytes);
    if (!bytes) return fail("the token is not base64url text of at most " +
                            std::to_string(jetrace::auth::kMaxTokenBytes) + " bytes");
    const auto token = jetrace::auth::parse_connect_token(*bytes, &error);
    if (!token) return fail("malformed token: " + error);
    nlohmann::json j;
    j["name"] = token->name;
    j["expires_unix_s"] = token->expires_unix_s;
    j["expires_in_s"] = token->expires_unix_s - unix_now_s();
    j["race_id"] = token->race_id;
    j["nonce"] = jetrace::auth::to_text(token->nonce);
    if (!inspect_key.empty()) {
        jetrace::auth::LoadedKey key;
        if (!jetrace::auth::load_key_file(inspect_key, key, error)) return fail(error);
        j["signature_valid"] = jetrace::auth::signature_valid(*token, key.public_key);
    }
    std::printf("%s\n", j.dump().c_str());
    return 0;
}
