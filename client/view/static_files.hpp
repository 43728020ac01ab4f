// Which file a page's GET names: the page's own files by bare name, and
// three.js's module files under /three/ from node_modules. Every request
// target is untrusted: only plain names are looked up (no "..", no hidden
// files, no other directory), and only files of known types.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace jetrace::view {

struct StaticFile {
    std::string path;
    std::string content_type;
};

/// The file `target` names, or none (404).
std::optional<StaticFile> resolve_static(std::string_view target, const std::string& web_dir,
                                         const std::string& node_modules_dir);

/// The whole file, or none if it cannot be read.
std::optional<std::string> read_whole_file(const std::string& path);

}  // namespace jetrace::view
