# LLVM's lld (Debian's lld, installed by tools/install-deps.sh) links the
# host programs: ddmr-hil and the test programs are 50-200 MB with their
# debug info, which GNU ld takes about 5 s each to link and lld about 1 s
# (measured on ddmr-hil), twice per `make test` (the normal and sanitizer
# trees). The programs are the same. -DDDMR_LLD=OFF links with the
# compiler's default linker.
option(DDMR_LLD "Link the host programs with lld when it is installed" ON)
if(DDMR_LLD AND CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    find_program(DDMR_LLD_PROGRAM ld.lld)
    if(DDMR_LLD_PROGRAM)
        add_link_options(-fuse-ld=lld)
    endif()
endif()
