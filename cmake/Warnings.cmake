# ddmr_warnings: an INTERFACE target carrying the project's warning flags.
# Linked PRIVATE by every project target, so flags never leak to consumers or
# to third-party code (simavr headers are included as SYSTEM).
add_library(ddmr_warnings INTERFACE)
target_compile_options(ddmr_warnings INTERFACE
    -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wsign-conversion
    -Wnon-virtual-dtor -Wold-style-cast -Wcast-align -Woverloaded-virtual
    -Wdouble-promotion -Wformat=2 -Wimplicit-fallthrough)
