#include "jetrace/track_io.hpp"

#include "jetrace/builtin_tracks.hpp"

#include <fstream>
#include <sstream>

namespace jetrace {

bool import_obj_file(const std::string& path, Track& out, std::string& error) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        error = "cannot open track file '" + path + "'";
        return false;
    }
    std::ostringstream buf;
    buf << in.rdbuf();
    if (in.bad()) {
        error = "cannot read track file '" + path + "'";
        return false;
    }
    std::string name = path;
    const auto slash = name.find_last_of('/');
    if (slash != std::string::npos) name = name.substr(slash + 1);
    if (name.size() > 4 && name.substr(name.size() - 4) == ".obj") name.resize(name.size() - 4);
    if (!import_obj(buf.str(), name, out, error)) {
        error = path + ": " + error;
        return false;
    }
    return true;
}

bool load_track(const std::string& spec, Track& out, std::string& error) {
    if (make_builtin_track(spec, out)) return true;
    if (spec.size() > 4 && spec.substr(spec.size() - 4) == ".obj") return import_obj_file(spec, out, error);
    error = "unknown track '" + spec + "': use a built-in name (";
    const auto names = builtin_track_names();
    for (std::size_t i = 0; i < names.size(); ++i) error += (i ? ", " : "") + names[i];
    error += ") or a path ending in .obj";
    return false;
}

}  // namespace jetrace
