# aarch64 cross toolchain for make test-arm64: Debian's g++-aarch64-linux-gnu against the Debian
# arm64 sysroot of scripts/arm64_sysroot.sh (RLD_SYSROOT); programs run under qemu-aarch64.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
if(NOT RLD_SYSROOT AND DEFINED ENV{RLD_SYSROOT})
  set(RLD_SYSROOT $ENV{RLD_SYSROOT})
endif()
list(APPEND CMAKE_TRY_COMPILE_PLATFORM_VARIABLES RLD_SYSROOT)  # CMake's own compiler checks
if(NOT RLD_SYSROOT)
  message(FATAL_ERROR "set RLD_SYSROOT to the arm64 sysroot (scripts/arm64_sysroot.sh)")
endif()
set(CMAKE_SYSROOT ${RLD_SYSROOT})
set(CMAKE_FIND_ROOT_PATH ${RLD_SYSROOT})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
# the libraries' own dependencies (TBB, BLAS, X11 of OpenCV's core) are found at link time here
set(CMAKE_EXE_LINKER_FLAGS_INIT
  "-Wl,-rpath-link,${RLD_SYSROOT}/usr/lib/aarch64-linux-gnu -Wl,-rpath-link,${RLD_SYSROOT}/lib/aarch64-linux-gnu")
set(CMAKE_SHARED_LINKER_FLAGS_INIT "${CMAKE_EXE_LINKER_FLAGS_INIT}")
set(CMAKE_CROSSCOMPILING_EMULATOR qemu-aarch64 -L ${RLD_SYSROOT})
