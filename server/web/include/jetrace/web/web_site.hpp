// The files the web port serves, read once at start into memory: the game
// page (client/view/web), the three.js modules it imports (node_modules)
// and the WebAssembly client (the emscripten build, tools/build.sh). The
// list is fixed here; no request path is ever joined to a directory.
#pragma once

#include "jetrace/web/web_transport.hpp"

#include <string>
#include <vector>

namespace jetrace::web {

struct SiteDirs {
    /// The page's own files (index.html, served as / with the WebAssembly
    /// client as its source).
    std::string page;
    /// npm's node_modules (three.js).
    std::string node_modules;
    /// The emscripten build's output (jetrace_web.js, jetrace_web.wasm).
    std::string wasm;
};

/// The site; every file of the list that cannot be read is named in
/// `missing` (the site then lacks it: 404).
WebSite load_site(const SiteDirs& dirs, std::vector<std::string>& missing);

}  // namespace jetrace::web
