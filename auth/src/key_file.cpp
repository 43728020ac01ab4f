// Key files: one line of text, permissions checked like ssh does.
#include "jetrace/auth/key_file.hpp"

#include <sodium.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string_view>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace jetrace::auth {

namespace {

constexpr std::string_view kSecretTag = "jetrace-ed25519-secret-key ";
constexpr std::string_view kPublicTag = "jetrace-ed25519-public-key ";

bool fail(std::string& error, const std::string& path, const std::string& what) {
    error = "key file '" + path + "': " + what;
    return false;
}

/// Writes `text` to `path` created with `mode` (O_EXCL unless overwrite).
bool write_file(const std::string& path, const std::string& text, mode_t mode, bool overwrite, std::string& error) {
    const int flags = O_WRONLY | O_CREAT | O_CLOEXEC | (overwrite ? O_TRUNC : O_EXCL);
    const int fd = ::open(path.c_str(), flags, mode);
    if (fd < 0) {
        return fail(error, path,
                    errno == EEXIST ? "exists already (pass --force to overwrite)" : std::strerror(errno));
    }
    // An overwritten file keeps its old mode: set it.
    bool ok = ::fchmod(fd, mode) == 0;
    std::size_t done = 0;
    while (ok && done < text.size()) {
        const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
        if (n < 0 && errno == EINTR) continue;
        ok = n > 0;
        if (ok) done += static_cast<std::size_t>(n);
    }
    const int saved = errno;
    ok = ::close(fd) == 0 && ok;
    if (!ok) return fail(error, path, std::strerror(saved != 0 ? saved : errno));
    return true;
}

}  // namespace

namespace {

// Reads a regular file of at most kMaxKeyFileBytes into `text`, with its
// mode. The error names what failed (without the path).
bool read_key_text(const std::string& path, std::string& text, mode_t& mode, std::string& error) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
    if (fd < 0) {
        error = std::strerror(errno);
        return false;
    }
    struct stat st {};
    bool ok = ::fstat(fd, &st) == 0;
    const std::string too_large = "larger than " + std::to_string(kMaxKeyFileBytes) + " bytes: not a key file";
    if (!ok) {
        error = std::strerror(errno);
    } else if (!S_ISREG(st.st_mode)) {
        ok = false;
        error = "not a regular file";
    } else if (static_cast<std::size_t>(st.st_size) > kMaxKeyFileBytes) {
        ok = false;
        error = too_large;
    } else {
        text.resize(kMaxKeyFileBytes + 1);
        std::size_t len = 0;
        while (len < text.size()) {
            const ssize_t n = ::read(fd, text.data() + len, text.size() - len);
            if (n < 0 && errno == EINTR) continue;
            if (n < 0) {
                ok = false;
                error = std::strerror(errno);
            }
            if (n <= 0) break;
            len += static_cast<std::size_t>(n);
        }
        text.resize(len);
        if (ok && len > kMaxKeyFileBytes) {
            ok = false;
            error = too_large;
        }
    }
    ::close(fd);
    mode = st.st_mode;
    return ok;
}

}  // namespace

bool load_key_file(const std::string& path, LoadedKey& out, std::string& error) {
    std::string text;
    mode_t mode = 0;
    if (!read_key_text(path, text, mode, error)) return fail(error, path, error);

    out = LoadedKey{};
    std::string_view body;
    if (text.starts_with(kSecretTag)) {
        out.has_secret = true;
        body = std::string_view(text).substr(kSecretTag.size());
    } else if (text.starts_with(kPublicTag)) {
        body = std::string_view(text).substr(kPublicTag.size());
    } else {
        return fail(error, path,
                    "not a jetrace key file (expected a line starting 'jetrace-ed25519-secret-key ' or "
                    "'jetrace-ed25519-public-key ')");
    }
    if (out.has_secret && (mode & (S_IRWXG | S_IRWXO)) != 0) {
        char octal[8];
        std::snprintf(octal, sizeof octal, "%04o", static_cast<unsigned>(mode & 07777));
        return fail(error, path,
                    std::string("permissions ") + octal + " are too open for a secret key: run chmod 600 '" + path + "'");
    }
    const std::size_t want = out.has_secret ? kSecretKeyBytes : kPublicKeyBytes;
    const auto bytes = from_text(body, want);
    if (!bytes || bytes->size() != want) {
        return fail(error, path, "the key is not " + std::to_string(want) + " bytes of base64url text");
    }
    if (out.has_secret) {
        std::memcpy(out.secret.data(), bytes->data(), want);
        // libsodium's secret key is seed | public key: both halves must agree.
        KeyPair again;
        crypto_sign_seed_keypair(again.public_key.data(), again.secret_key.data(), out.secret.data());
        if (!equal_secret(again.secret_key, out.secret)) {
            return fail(error, path, "corrupt secret key (its public half does not match its seed)");
        }
        out.public_key = again.public_key;
        sodium_memzero(again.secret_key.data(), again.secret_key.size());
    } else {
        std::memcpy(out.public_key.data(), bytes->data(), want);
    }
    return true;
}

bool write_key_files(const std::string& secret_path, const KeyPair& keys, bool overwrite, std::string& error) {
    std::string secret = std::string(kSecretTag) + to_text(keys.secret_key) + "\n";
    const bool ok = write_file(secret_path, secret, 0600, overwrite, error);
    sodium_memzero(secret.data(), secret.size());
    if (!ok) return false;
    return write_file(secret_path + ".pub", std::string(kPublicTag) + to_text(keys.public_key) + "\n", 0644, overwrite,
                      error);
}

}  // namespace jetrace::auth
