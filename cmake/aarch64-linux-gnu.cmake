# Cross-compiling for aarch64 Linux with Debian's g++-aarch64-linux-gnu; the
# programs run on an x86-64 host under qemu user mode (qemu-user), which CMake
# and CTest use as the emulator. Used by tools/cross.sh with
# -DJETRACE_PORTABLE_ONLY=ON (no compiled third-party library is needed).
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)

set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
set(CMAKE_CROSSCOMPILING_EMULATOR "qemu-aarch64;-L;/usr/aarch64-linux-gnu")

# Libraries and headers come from the aarch64 sysroot only, programs (flatc,
# ...) from the host. Packages are looked up in the sysroot first and then on
# the host: that is how Eigen3's CMake config (/usr/share/eigen3/cmake) is
# found; Eigen is header-only and architecture-independent. The portable
# build asks for no package that has a compiled library.
set(CMAKE_FIND_ROOT_PATH /usr/aarch64-linux-gnu)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE BOTH)
