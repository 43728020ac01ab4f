# jetrace_host_headers: the host's header-only libraries that the portable
# build uses (CLI11, nlohmann-json), for any compiler, cross compilers
# included. Adding /usr/include itself to a cross compiler's include path
# would pull in the host's C library headers, so the include directory is a
# folder of the build tree holding a symlink to each library's own folder.
set(_jetrace_host_headers_dir "${CMAKE_BINARY_DIR}/host_headers")
file(MAKE_DIRECTORY "${_jetrace_host_headers_dir}")
foreach(_dir IN ITEMS CLI nlohmann)
  if(NOT IS_DIRECTORY "/usr/include/${_dir}")
    message(FATAL_ERROR "/usr/include/${_dir} not found (Debian packages libcli11-dev, nlohmann-json3-dev: tools/setup.sh)")
  endif()
  file(CREATE_LINK "/usr/include/${_dir}" "${_jetrace_host_headers_dir}/${_dir}" SYMBOLIC)
endforeach()
add_library(jetrace_host_headers INTERFACE)
target_include_directories(jetrace_host_headers SYSTEM INTERFACE "${_jetrace_host_headers_dir}")
