#include "gltf_files.hpp"

#include "jetrace/tracks/mesh_import.hpp"

#include <fstream>
#include <sys/stat.h>

namespace jetrace::detail::gltf_files {
namespace {

bool fail(std::string& error, std::string message) {
    error = std::move(message);
    return false;
}

bool regular_file_size(const std::string& path, std::size_t& size, std::string& error) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) return fail(error, "cannot open '" + path + "'");
    if (!S_ISREG(st.st_mode)) return fail(error, "'" + path + "' is not a regular file");
    size = static_cast<std::size_t>(st.st_size);
    if (size > kMaxTrackFileBytes) {
        return fail(error, "'" + path + "' is " + std::to_string(size) + " bytes; at most " +
                               std::to_string(kMaxTrackFileBytes) + " are read");
    }
    return true;
}

}  // namespace

bool no_image(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int, void*) {
    return true;  // textures are irrelevant to a track; never decoded
}

bool read_whole(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* allowed) {
    if (allowed && !*static_cast<const bool*>(allowed)) {
        if (err) *err += "external file '" + path + "' is not allowed here\n";
        return false;
    }
    std::size_t size = 0;
    std::string e;
    if (!regular_file_size(path, size, e)) {
        if (err) *err += e + "\n";
        return false;
    }
    std::ifstream in(path, std::ios::binary);
    out->resize(size);
    if (!in.read(reinterpret_cast<char*>(out->data()), static_cast<std::streamsize>(size))) {
        if (err) *err += "cannot read '" + path + "'\n";
        return false;
    }
    return true;
}

bool file_exists(const std::string& path, void* allowed) {
    if (allowed && !*static_cast<const bool*>(allowed)) return false;
    struct stat st {};
    return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}
std::string expand_path(const std::string& path, void*) { return path; }  // no ~ or $VAR expansion
bool no_write(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
    if (err) *err += "writing is disabled\n";
    return false;
}

}  // namespace jetrace::detail::gltf_files
