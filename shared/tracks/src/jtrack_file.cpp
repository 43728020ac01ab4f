// .jtrack files: read through a read-only memory map (the kernel's page
// cache is then shared by every process that loads the same file; nothing is
// copied before the checks), written through a temporary file renamed into
// place (a failed write leaves no partial file under the name).
#include "jetrace/tracks/jtrack.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

namespace jetrace {
namespace {

// A file descriptor closed on scope exit.
struct Fd {
    int fd = -1;
    ~Fd() {
        if (fd >= 0) ::close(fd);
    }
};

// A read-only mapping unmapped on scope exit.
struct Mapping {
    void* data = MAP_FAILED;
    std::size_t size = 0;
    ~Mapping() {
        if (data != MAP_FAILED) ::munmap(data, size);
    }
};

std::string os_error() { return std::strerror(errno); }

// The largest valid file (the layout's size with every count at its limit:
// three unshared vertices of 24 bytes and three 4-byte indices a triangle),
// so that nothing larger is mapped.
constexpr std::uint64_t kMaxJtrackBytes = kJtrackHeaderBytes + kJtrackMaxNameBytes + 72ull * kMaxTrackTriangles +
                                          12ull * kMaxTrackTriangles + 8 + 184ull * kJtrackMaxGates +
                                          72ull * kJtrackMaxSpawns;

}  // namespace

bool load_jtrack_file(const std::string& path, Track& out, std::string& error) {
    Fd f{::open(path.c_str(), O_RDONLY | O_CLOEXEC)};
    if (f.fd < 0) {
        error = "cannot open track file '" + path + "': " + os_error();
        return false;
    }
    struct stat st {};
    if (::fstat(f.fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        error = "track file '" + path + "' is not a regular file";
        return false;
    }
    const auto size = static_cast<std::uint64_t>(st.st_size);
    if (size > kMaxJtrackBytes) {
        error = path + ": file is " + std::to_string(size) + " bytes, larger than any valid .jtrack (" +
                std::to_string(kMaxJtrackBytes) + ")";
        return false;
    }
    Mapping m;
    if (size > 0) {
        m.size = static_cast<std::size_t>(size);
        m.data = ::mmap(nullptr, m.size, PROT_READ, MAP_PRIVATE | MAP_POPULATE, f.fd, 0);
        if (m.data == MAP_FAILED) {
            error = "cannot map track file '" + path + "': " + os_error();
            return false;
        }
    }
    const std::span<const std::uint8_t> bytes(static_cast<const std::uint8_t*>(m.data == MAP_FAILED ? nullptr : m.data),
                                              m.size);
    if (!decode_jtrack(bytes, out, error)) {
        error = path + ": " + error;
        return false;
    }
    return true;
}

bool file_is_jtrack(const std::string& path) {
    Fd f{::open(path.c_str(), O_RDONLY | O_CLOEXEC)};
    if (f.fd < 0) return false;
    struct stat st {};
    if (::fstat(f.fd, &st) != 0 || !S_ISREG(st.st_mode)) return false;
    std::uint8_t head[sizeof kJtrackMagic] = {};
    return ::pread(f.fd, head, sizeof head, 0) == static_cast<ssize_t>(sizeof head) && is_jtrack(head);
}

bool write_jtrack_file(const Track& track, const std::string& path, std::string& error) {
    const std::vector<std::uint8_t> bytes = encode_jtrack(track);
    const std::string tmp = path + ".tmp";
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (f == nullptr) {
        error = "cannot create '" + tmp + "': " + os_error();
        return false;
    }
    const bool written = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
    const bool closed = std::fclose(f) == 0;
    if (!written || !closed) {
        error = "cannot write '" + tmp + "': " + os_error();
        std::remove(tmp.c_str());
        return false;
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        error = "cannot rename '" + tmp + "' to '" + path + "': " + os_error();
        std::remove(tmp.c_str());
        return false;
    }
    return true;
}

}  // namespace jetrace
