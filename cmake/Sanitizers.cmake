# ddmr_sanitizers: an INTERFACE target that turns on ASan + UBSan when
# DDMR_SANITIZE is ON. Used by `make test` in a separate build tree
# (build-asan/), so the main build stays fast.
add_library(ddmr_sanitizers INTERFACE)
if(DDMR_SANITIZE)
    target_compile_options(ddmr_sanitizers INTERFACE
        -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all)
    target_link_options(ddmr_sanitizers INTERFACE -fsanitize=address,undefined)
endif()
