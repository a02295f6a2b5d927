# Every third-party dependency, found once, from Debian's packages
# (installed by tools/install-deps.sh, called by `make deps`).
# Nothing is downloaded at build time.
find_package(PkgConfig REQUIRED)
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(yaml-cpp REQUIRED)
find_package(nlohmann_json 3.10 REQUIRED)
find_package(fmt REQUIRED)
find_package(CLI11 REQUIRED)
find_package(Threads REQUIRED)
find_package(OpenSSL REQUIRED COMPONENTS Crypto)
find_package(pugixml REQUIRED)  # JUnit XML of `ddmr-hil scenario`
# NLopt (libnlopt-cxx-dev: the C library and nlopt.hpp): `ddmr-hil calibrate`'s optimiser.
find_package(NLopt 2.7 REQUIRED)
# libinih (libinih-dev): PlatformIO projects' platformio.ini (`run --platformio`).
pkg_check_modules(INIH REQUIRED IMPORTED_TARGET inih)

if(DDMR_WITH_HIL)
    # simavr 1.6: Debian ships only the static library and a pkg-config file.
    pkg_check_modules(SIMAVR REQUIRED IMPORTED_TARGET simavr>=1.6)
    find_library(LIBELF_LIBRARY elf REQUIRED)
    find_package(ZLIB REQUIRED)
endif()

if(DDMR_BUILD_TESTS)
    find_package(GTest REQUIRED)
endif()
if(DDMR_BUILD_BENCH)
    find_package(benchmark REQUIRED)
endif()
