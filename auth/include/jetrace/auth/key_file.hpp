// Key files of private races (jetrace-token keygen writes them,
// jetrace-server --key-file and jetrace-token issue read them). One line of
// text each:
//   FILE      jetrace-ed25519-secret-key <base64url of the 64-byte secret key>
//   FILE.pub  jetrace-ed25519-public-key <base64url of the 32-byte public key>
// A secret key file must be readable by its owner only (mode 0600 or
// stricter); reading refuses anything else, as ssh does.
#pragma once

#include "jetrace/auth/connect_token.hpp"

#include <string>

namespace jetrace::auth {

/// Largest key file read (unit: bytes): a key file is one short line.
inline constexpr std::size_t kMaxKeyFileBytes = 1024;

struct LoadedKey {
    /// The file held a secret key (then `secret` is set), else a public key.
    bool has_secret = false;
    PublicKey public_key{};
    SecretKey secret{};
};

/// Reads a public or secret key file. False with a message naming the file
/// on a missing or unreadable file, a non-regular file, more than
/// kMaxKeyFileBytes, a bad format, a secret key file others may read, or a
/// secret key whose halves do not belong together.
bool load_key_file(const std::string& path, LoadedKey& out, std::string& error);

/// Writes `secret_path` (mode 0600) and `secret_path + ".pub"` (mode 0644).
/// Refuses to overwrite existing files unless `overwrite`.
bool write_key_files(const std::string& secret_path, const KeyPair& keys, bool overwrite, std::string& error);

}  // namespace jetrace::auth
