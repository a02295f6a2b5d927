# add_arduino_sketch(<target> SKETCH <dir/name.ino> OUTPUT <path.elf> [FQBN <fqbn>] [MCU <mcu>]
#                    [LIBRARIES <dir>...])
#
# FQBN: the board (default arduino:avr:uno; arduino:avr:nano:cpu=atmega328,
# arduino:avr:pro:cpu=8MHzatmega328, arduino:avr:mega:cpu=atmega2560); MCU:
# its chip for the size report (default atmega328p; atmega2560 for the Mega).
# LIBRARIES: folders of Arduino libraries. arduino-builder is given, as
# `ddmr-hil` gives it (tools/common/arduino_libraries.hpp, docs/firmware.md),
# the existing folders among: the sketch's src/, LIBRARIES, and the
# sketchbook's libraries/ ($ARDUINO_DIRECTORIES_USER/libraries, else
# ~/Arduino/libraries, as found when CMake configures).
#
# Builds an Arduino sketch exactly as the Arduino IDE does, with Debian's
# arduino-builder and Arduino AVR core: the IDE's .ino preprocessing (ctags
# prototypes), the core library, LTO. Writes <path.elf> and <path.hex>, and
# prints the flash and RAM use arduino-builder reports.
#
# Debian's gcc-avr 5.4 does not define DECIMAL_DIG in C++ mode, which the
# core's WString.cpp needs; it is defined as the compiler's own
# __DECIMAL_DIG__ (9 on AVR, where double is 32-bit) through the platform's
# compiler.cpp.extra_flags preference. Nothing else differs from the IDE.
find_program(ARDUINO_BUILDER arduino-builder REQUIRED)
find_program(AVR_SIZE avr-size REQUIRED)
find_program(AVR_OBJCOPY avr-objcopy REQUIRED)
set(DDMR_ARDUINO_HARDWARE_DIRS /usr/share/arduino-builder /usr/share/arduino/hardware)
set(DDMR_ARDUINO_TOOLS_DIR /usr/share/arduino-builder)
set(DDMR_ARDUINO_FQBN arduino:avr:uno)
# The one preference that differs from the IDE (see above).
set(DDMR_ARDUINO_EXTRA_PREFS "compiler.cpp.extra_flags=-DDECIMAL_DIG=__DECIMAL_DIG__")
foreach(dir IN LISTS DDMR_ARDUINO_HARDWARE_DIRS)
    if(NOT IS_DIRECTORY "${dir}")
        message(FATAL_ERROR "Arduino hardware folder ${dir} is missing: run `make deps` "
                            "(packages arduino-core-avr and arduino-builder)")
    endif()
endforeach()

function(add_arduino_sketch target)
    cmake_parse_arguments(ARG "" "SKETCH;OUTPUT;FQBN;MCU" "LIBRARIES" ${ARGN})
    if(NOT ARG_FQBN)
        set(ARG_FQBN ${DDMR_ARDUINO_FQBN})
    endif()
    if(NOT ARG_MCU)
        set(ARG_MCU atmega328p)
    endif()
    get_filename_component(sketch_name "${ARG_SKETCH}" NAME_WE)
    get_filename_component(out_dir "${ARG_OUTPUT}" DIRECTORY)
    get_filename_component(out_we "${ARG_OUTPUT}" NAME_WE)
    set(work_dir "${CMAKE_CURRENT_BINARY_DIR}/${target}.arduino")
    set(hex "${out_dir}/${out_we}.hex")
    set(hardware_args)
    foreach(dir IN LISTS DDMR_ARDUINO_HARDWARE_DIRS)
        list(APPEND hardware_args -hardware "${dir}")
    endforeach()
    # Library folders: arduino-builder aborts on one that does not exist.
    get_filename_component(sketch_dir "${ARG_SKETCH}" DIRECTORY)
    set(sketchbook_libraries)
    if(DEFINED ENV{ARDUINO_DIRECTORIES_USER} AND NOT "$ENV{ARDUINO_DIRECTORIES_USER}" STREQUAL "")
        set(sketchbook_libraries "$ENV{ARDUINO_DIRECTORIES_USER}/libraries")
    elseif(DEFINED ENV{HOME} AND NOT "$ENV{HOME}" STREQUAL "")
        set(sketchbook_libraries "$ENV{HOME}/Arduino/libraries")
    endif()
    set(library_args)
    foreach(dir IN ITEMS "${sketch_dir}/src" ${ARG_LIBRARIES} ${sketchbook_libraries})
        if(IS_DIRECTORY "${dir}")
            list(APPEND library_args -libraries "${dir}")
        elseif(NOT dir STREQUAL "${sketch_dir}/src" AND NOT dir STREQUAL "${sketchbook_libraries}")
            message(FATAL_ERROR "add_arduino_sketch(${target}): LIBRARIES ${dir}: no such folder")
        endif()
    endforeach()
    add_custom_command(
        OUTPUT "${ARG_OUTPUT}" "${hex}"
        COMMAND ${CMAKE_COMMAND} -E rm -rf "${work_dir}"
        COMMAND ${CMAKE_COMMAND} -E make_directory "${work_dir}" "${out_dir}"
        COMMAND ${ARDUINO_BUILDER} -compile ${hardware_args}
                -tools "${DDMR_ARDUINO_TOOLS_DIR}"
                -fqbn ${ARG_FQBN}
                ${library_args}
                -build-path "${work_dir}"
                "-prefs=${DDMR_ARDUINO_EXTRA_PREFS}"
                "${ARG_SKETCH}"
        COMMAND ${CMAKE_COMMAND} -E copy "${work_dir}/${sketch_name}.ino.elf" "${ARG_OUTPUT}"
        COMMAND ${CMAKE_COMMAND} -E copy "${work_dir}/${sketch_name}.ino.hex" "${hex}"
        COMMAND ${AVR_SIZE} --format=avr --mcu=${ARG_MCU} "${ARG_OUTPUT}"
        DEPENDS "${ARG_SKETCH}"
        COMMENT "Building Arduino sketch ${sketch_name} for ${ARG_FQBN} with arduino-builder"
        VERBATIM)
    add_custom_target(${target} ALL DEPENDS "${ARG_OUTPUT}" "${hex}")
endfunction()
