#include "jetrace/replay/source.hpp"

#include <sys/stat.h>

#include <cerrno>
#include <cstring>

namespace jetrace::replay {

std::size_t SpanSource::read(std::uint8_t* dst, std::size_t n) {
    const std::size_t k = n < bytes_.size() - off_ ? n : bytes_.size() - off_;
    if (k > 0) std::memcpy(dst, bytes_.data() + off_, k);
    off_ += k;
    return k;
}

FileSource::~FileSource() {
    if (file_) std::fclose(file_);
}

bool FileSource::open(const std::string& path, std::string& error, std::uint64_t max_bytes) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) {
        error = "cannot open '" + path + "': " + std::strerror(errno);
        return false;
    }
    if (S_ISDIR(st.st_mode)) {
        error = "'" + path + "' is a directory, not a replay file";
        return false;
    }
    if (!S_ISREG(st.st_mode)) {
        error = "'" + path + "' is not a regular file (a device, pipe or socket), not a replay file";
        return false;
    }
    if (static_cast<std::uint64_t>(st.st_size) > max_bytes) {
        error = "'" + path + "' has " + std::to_string(st.st_size) + " bytes, more than the " +
                std::to_string(max_bytes) + " a replay may have";
        return false;
    }
    file_ = std::fopen(path.c_str(), "rb");
    if (!file_) {
        error = "cannot open '" + path + "': " + std::strerror(errno);
        return false;
    }
    size_ = static_cast<std::uint64_t>(st.st_size);
    return true;
}

std::size_t FileSource::read(std::uint8_t* dst, std::size_t n) {
    if (!file_ || n == 0) return 0;
    const std::size_t k = std::fread(dst, 1, n, file_);
    if (k < n && std::ferror(file_)) error_ = std::string("read error: ") + std::strerror(errno);
    return k;
}

}  // namespace jetrace::replay
