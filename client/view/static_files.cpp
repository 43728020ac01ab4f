#include "static_files.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>

namespace jetrace::view {

namespace {

bool plain_segment(std::string_view s) {
    if (s.empty() || s.size() > 128 || s.front() == '.') return false;
    for (char c : s) {
        const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
                        c == '-' || c == '.';
        if (!ok) return false;
    }
    return true;
}

std::string type_of(std::string_view name) {
    const auto ends = [&](std::string_view ext) {
        return name.size() > ext.size() && name.substr(name.size() - ext.size()) == ext;
    };
    if (ends(".html")) return "text/html; charset=utf-8";
    if (ends(".js")) return "text/javascript; charset=utf-8";
    if (ends(".css")) return "text/css; charset=utf-8";
    return "";
}

std::optional<StaticFile> existing(const std::filesystem::path& p, std::string type) {
    std::error_code ec;
    if (type.empty() || !std::filesystem::is_regular_file(p, ec)) return std::nullopt;
    return StaticFile{p.string(), std::move(type)};
}

}  // namespace

std::optional<StaticFile> resolve_static(std::string_view target, const std::string& web_dir,
                                         const std::string& node_modules_dir) {
    if (const auto q = target.find('?'); q != std::string_view::npos) target = target.substr(0, q);
    if (target == "/") return existing(std::filesystem::path(web_dir) / "index.html", type_of("index.html"));
    if (target.size() < 2 || target.front() != '/') return std::nullopt;
    const std::string_view rest = target.substr(1);
    if (plain_segment(rest)) return existing(std::filesystem::path(web_dir) / rest, type_of(rest));
    constexpr std::string_view kThree = "three/";
    if (rest.substr(0, kThree.size()) != kThree) return std::nullopt;
    std::filesystem::path p = std::filesystem::path(node_modules_dir) / "three";
    std::string_view tail = rest.substr(kThree.size());
    int depth = 0;
    while (!tail.empty()) {
        const auto slash = tail.find('/');
        const std::string_view seg = tail.substr(0, slash);
        if (!plain_segment(seg) || ++depth > 8) return std::nullopt;
        p /= seg;
        tail = slash == std::string_view::npos ? std::string_view{} : tail.substr(slash + 1);
        if (slash != std::string_view::npos && tail.empty()) return std::nullopt;
    }
    const std::string name = p.filename().string();
    return name.size() > 3 && name.substr(name.size() - 3) == ".js" ? existing(p, type_of(name)) : std::nullopt;
}

std::optional<std::string> read_whole_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return std::nullopt;
    std::ostringstream s;
    s << in.rdbuf();
    if (in.bad()) return std::nullopt;
    return s.str();
}

}  // namespace jetrace::view
