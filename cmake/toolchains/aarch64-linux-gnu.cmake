# Cross-compiles for 64-bit ARM Linux (AArch64, Debian's g++-aarch64-linux-gnu); executables
# are linked statically and run under qemu-aarch64 (Debian's qemu-user), which CTest uses as
# the emulator. Eigen and doctest are header-only: their host CMake packages serve.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
set(CMAKE_EXE_LINKER_FLAGS_INIT "-static")
find_program(GRIP_QEMU_AARCH64 qemu-aarch64 REQUIRED)
set(CMAKE_CROSSCOMPILING_EMULATOR ${GRIP_QEMU_AARCH64})
