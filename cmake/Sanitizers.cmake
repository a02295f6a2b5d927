# ddmr_sanitizers: an INTERFACE target that turns on ASan + UBSan when
# DDMR_SANITIZE is ON. Used by `make test` in a separate build tree
# (build-asan/), so the main build stays fast.
add_library(ddmr_sanitizers INTERFACE)
if(DDMR_SANITIZE)
    # -Wno-maybe-uninitialized: with -fsanitize=address GCC 12 reports false
    # "may be used uninitialized" warnings inside libstdc++'s std::regex and
    # std::function (GCC bugs 105562, 107138); the normal build keeps the
    # warning, so real cases are still caught there.
    # -O1 -g1 (after the build type's -O2 -g, so they win): AddressSanitizer's
    # recommended optimisation level, and line tables only (file:line in
    # every sanitizer report, no variable info). Measured on
    # tools/firmware_run.cpp with the sanitizers: 106 s at -O2 -g, 44 s at
    # -O1 -g1; the sanitizer tree builds in well under half the time.
    target_compile_options(ddmr_sanitizers INTERFACE
        -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all
        -Wno-maybe-uninitialized -O1 -g1)
    target_link_options(ddmr_sanitizers INTERFACE -fsanitize=address,undefined)
endif()
