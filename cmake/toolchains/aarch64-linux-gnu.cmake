# Cross-compiles REngine for 64-bit ARM Linux on a Debian x86-64 machine, with Debian's
# cross compilers and the arm64 multiarch libraries (dpkg --add-architecture arm64), which
# install beside the native ones under /usr/lib/aarch64-linux-gnu: the sysroot is /, and
# CMake finds the arm64 libraries through CMAKE_LIBRARY_ARCHITECTURE. tools/cross_check.sh
# uses it; the executables run under qemu-aarch64 (CMAKE_CROSSCOMPILING_EMULATOR).
#   cmake -S . -B build-arm64 -DCMAKE_TOOLCHAIN_FILE=cmake/toolchains/aarch64-linux-gnu.cmake
# RENGINE_CROSS_COMPILER=clang builds with clang for --target=aarch64-linux-gnu instead of
# aarch64-linux-gnu-g++ (it uses the same GNU cross binutils, libstdc++ and C library).
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_LIBRARY_ARCHITECTURE aarch64-linux-gnu)

if(NOT DEFINED RENGINE_CROSS_COMPILER)
  set(RENGINE_CROSS_COMPILER gcc)
endif()
set(RENGINE_CROSS_COMPILER "${RENGINE_CROSS_COMPILER}" CACHE STRING "gcc or clang")
if(RENGINE_CROSS_COMPILER STREQUAL "clang")
  set(CMAKE_C_COMPILER clang)
  set(CMAKE_CXX_COMPILER clang++)
  set(CMAKE_C_COMPILER_TARGET aarch64-linux-gnu)
  set(CMAKE_CXX_COMPILER_TARGET aarch64-linux-gnu)
else()
  set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
  set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
endif()

# Programs run on the build machine; libraries, headers and packages are the target's
# (the arm64 ones come first through CMAKE_LIBRARY_ARCHITECTURE; header-only packages such
# as Eigen, nlohmann-json and CLI11 are architecture-independent and found where they are).
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)

find_program(RENGINE_QEMU_AARCH64 qemu-aarch64)
if(RENGINE_QEMU_AARCH64)
  set(CMAKE_CROSSCOMPILING_EMULATOR "${RENGINE_QEMU_AARCH64}")
endif()
