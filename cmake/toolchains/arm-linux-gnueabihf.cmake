# Cross-compiles for 32-bit ARM Linux (armv7 hard-float, Debian's g++-arm-linux-gnueabihf);
# executables are linked statically and run under qemu-arm (Debian's qemu-user), which CTest
# uses as the emulator. Eigen and doctest are header-only: their host CMake packages serve.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR arm)
set(CMAKE_C_COMPILER arm-linux-gnueabihf-gcc)
set(CMAKE_CXX_COMPILER arm-linux-gnueabihf-g++)
set(CMAKE_EXE_LINKER_FLAGS_INIT "-static")
# Silence the ABI notes about GCC 7.1 parameter passing (libstdc++ vectors in doctest).
set(CMAKE_CXX_FLAGS_INIT "-Wno-psabi")
find_program(GRIP_QEMU_ARM qemu-arm REQUIRED)
set(CMAKE_CROSSCOMPILING_EMULATOR ${GRIP_QEMU_ARM})
