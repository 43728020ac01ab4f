#include "jetrace/web/web_site.hpp"

#include <zlib.h>

#include <fstream>
#include <sstream>
#include <string_view>

namespace jetrace::web {

namespace {

struct Entry {
    const char* request;
    int dir;  // 0 page, 1 node_modules, 2 wasm
    const char* file;
};

constexpr Entry kFiles[] = {
    {"/", 0, "index.html"},
    {"/app.js", 0, "app.js"},
    {"/cameras.js", 0, "cameras.js"},
    {"/frame_stats.js", 0, "frame_stats.js"},
    {"/keys.js", 0, "keys.js"},
    {"/scene.js", 0, "scene.js"},
    {"/ui.js", 0, "ui.js"},
    {"/sources.js", 0, "sources.js"},
    {"/hud.js", 0, "hud.js"},
    {"/client_source.js", 0, "client_source.js"},
    {"/client_worker.js", 0, "client_worker.js"},
    {"/rtc_link.js", 0, "rtc_link.js"},
    {"/close_text.js", 0, "close_text.js"},
    {"/style.css", 0, "style.css"},
    {"/three/build/three.module.js", 1, "three/build/three.module.js"},
    {"/three/build/three.core.js", 1, "three/build/three.core.js"},
    {"/three/examples/jsm/renderers/CSS2DRenderer.js", 1, "three/examples/jsm/renderers/CSS2DRenderer.js"},
    {"/three/examples/jsm/controls/OrbitControls.js", 1, "three/examples/jsm/controls/OrbitControls.js"},
    {"/jetrace_web.js", 2, "jetrace_web.js"},
    {"/jetrace_web.wasm", 2, "jetrace_web.wasm"},
};

std::string type_of(const std::string& name) {
    const auto ends = [&](const std::string& ext) {
        return name.size() > ext.size() && name.compare(name.size() - ext.size(), ext.size(), ext) == 0;
    };
    if (ends(".html")) return "text/html; charset=utf-8";
    if (ends(".js")) return "text/javascript; charset=utf-8";
    if (ends(".css")) return "text/css; charset=utf-8";
    if (ends(".wasm")) return "application/wasm";
    return "application/octet-stream";
}

bool read_file(const std::string& path, std::string& out) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return false;
    std::ostringstream s;
    s << in.rdbuf();
    if (in.bad()) return false;
    out = s.str();
    return true;
}

void replace_once(std::string& text, std::string_view from, std::string_view to) {
    if (const auto at = text.find(from); at != std::string::npos) text.replace(at, from.size(), to);
}

/// `bytes` gzip-compressed (zlib, level 9), or "" if that does not save a
/// tenth (a WebAssembly module compresses well, a small file may not).
std::string gzip(const std::string& bytes) {
    z_stream z{};
    if (deflateInit2(&z, 9, Z_DEFLATED, 15 + 16, 9, Z_DEFAULT_STRATEGY) != Z_OK) return {};
    std::string out(deflateBound(&z, static_cast<uLong>(bytes.size())) + 32, '\0');
    z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data()));
    z.avail_in = static_cast<uInt>(bytes.size());
    z.next_out = reinterpret_cast<Bytef*>(out.data());
    z.avail_out = static_cast<uInt>(out.size());
    const int rc = deflate(&z, Z_FINISH);
    out.resize(z.total_out);
    deflateEnd(&z);
    if (rc != Z_STREAM_END || out.size() * 10 > bytes.size() * 9) return {};
    return out;
}

}  // namespace

WebSite load_site(const SiteDirs& dirs, std::vector<std::string>& missing) {
    const std::string* roots[] = {&dirs.page, &dirs.node_modules, &dirs.wasm};
    WebSite site;
    for (const Entry& e : kFiles) {
        const std::string path = *roots[e.dir] + "/" + e.file;
        WebFile f;
        f.content_type = type_of(e.file);
        if (!read_file(path, f.bytes)) {
            missing.push_back(path);
            continue;
        }
        // The same page as jetrace-view's, its race coming from the client
        // library in WebAssembly instead of jetrace-view's socket.
        if (std::string_view(e.request) == "/") replace_once(f.bytes, "data-source=\"viewer\"", "data-source=\"client\"");
        f.gzipped = gzip(f.bytes);
        site.emplace(e.request, std::move(f));
    }
    return site;
}

}  // namespace jetrace::web
