// Durable file writes and the start-up check of jetrace-server's files.
#include "jetrace/server/host_files.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace jetrace::server {

namespace {

std::string directory_of(const std::string& path) {
    const auto slash = path.find_last_of('/');
    if (slash == std::string::npos) return ".";
    return slash == 0 ? "/" : path.substr(0, slash);
}

std::string failure(const std::string& what, const std::string& path) {
    return what + " '" + path + "': " + std::strerror(errno);
}

bool write_all(int fd, const std::string& content) {
    std::size_t off = 0;
    while (off < content.size()) {
        const ssize_t n = ::write(fd, content.data() + off, content.size() - off);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        off += static_cast<std::size_t>(n);
    }
    return true;
}

}  // namespace

bool write_file_atomically(const std::string& path, const std::string& content, std::string& error) {
    const std::string tmp = path + ".tmp";
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) {
        error = failure("cannot create the temporary file of", path) + " (" + tmp + ")";
        return false;
    }
    bool ok = write_all(fd, content);
    if (!ok) error = failure("cannot write", path) + " (temporary file " + tmp + ")";
    if (ok && ::fsync(fd) != 0) {
        error = failure("cannot fsync", path) + " (temporary file " + tmp + ")";
        ok = false;
    }
    if (::close(fd) != 0 && ok) {
        error = failure("cannot close", path) + " (temporary file " + tmp + ")";
        ok = false;
    }
    if (ok && std::rename(tmp.c_str(), path.c_str()) != 0) {
        error = failure("cannot rename the temporary file over", path);
        ok = false;
    }
    if (!ok) {
        ::unlink(tmp.c_str());
        return false;
    }
    const std::string dir = directory_of(path);
    const int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dfd < 0 || ::fsync(dfd) != 0) {
        error = failure("cannot fsync the directory of", path);
        if (dfd >= 0) ::close(dfd);
        return false;
    }
    ::close(dfd);
    return true;
}

bool check_can_create(const std::string& path, std::string& error) {
    struct stat st{};
    if (::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode)) {
        error = "'" + path + "' is a directory";
        return false;
    }
    const std::string dir = directory_of(path);
    const std::string probe = dir + "/.jetrace-probe-" + std::to_string(::getpid());
    const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
    if (fd < 0) {
        error = failure("cannot create files in the directory '" + dir + "' of", path);
        return false;
    }
    ::close(fd);
    ::unlink(probe.c_str());
    return true;
}

}  // namespace jetrace::server
