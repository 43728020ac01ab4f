// tinygltf's file-system and image callbacks for jetrace: regular files of
// at most kMaxTrackFileBytes only, no path expansion, no writing, images
// never decoded. Internal to jetrace::tracks (gltf_import.cpp).
#pragma once

#include <tiny_gltf.h>

#include <string>
#include <vector>

namespace jetrace::detail::gltf_files {

bool no_image(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int, void*);
/// user_data: a bool, false when no file may be read (bytes from memory).
bool read_whole(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* allowed);
bool file_exists(const std::string& path, void* allowed);
std::string expand_path(const std::string& path, void*);
bool no_write(std::string* err, const std::string&, const std::vector<unsigned char>&, void*);

}  // namespace jetrace::detail::gltf_files
