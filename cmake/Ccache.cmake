# ccache (Debian's ccache, installed by tools/install-deps.sh) in front of the
# host compilers: the normal and sanitizer trees, and worktrees of the same
# checkout, rebuild only what changed. CCACHE_BASEDIR makes the cache hit
# across checkouts at different paths. -DDDMR_CCACHE=OFF builds without it.
option(DDMR_CCACHE "Compile through ccache when it is installed" ON)
if(DDMR_CCACHE)
    find_program(DDMR_CCACHE_PROGRAM ccache)
    if(DDMR_CCACHE_PROGRAM)
        set(CMAKE_C_COMPILER_LAUNCHER
            ${CMAKE_COMMAND} -E env CCACHE_BASEDIR=${CMAKE_SOURCE_DIR} CCACHE_NOHASHDIR=1 ${DDMR_CCACHE_PROGRAM})
        set(CMAKE_CXX_COMPILER_LAUNCHER ${CMAKE_C_COMPILER_LAUNCHER})
    endif()
endif()
