# avr-gdb settings and commands for debugging a firmware that ddmr-hil runs
# (`ddmr-hil run --gdb PORT`, README: "Debugging the firmware with avr-gdb").
#
#   build/ddmr-hil run --gdb 1234 --out out/debug &
#   avr-gdb -x tools/ddmr.gdbinit build/firmware/ddmr_tracking.elf
#   (gdb) hil 1234
#   (gdb) break ddmr_tracking.ino:182      # a source line: loop() is inlined into main()
#   (gdb) continue
#   (gdb) pose
#   (gdb) detach                           # the run goes on at full speed

set confirm off
set pagination off

# avr-gdb reads a file's line tables only when it needs them, so
# `break ddmr_tracking.ino:182` would say "No source file named ..." until
# they are read. The firmware is small: read them all now (the same as
# starting avr-gdb with -readnow).
maint expand-symtabs

define hil
  target remote 127.0.0.1:$arg0
end
document hil
Attach to `ddmr-hil run --gdb PORT` (loopback only): hil PORT
end

# The LTO build's debug information gives the sketch's globals no type:
# read them as the sketch declares them.
define pose
  printf "Ex %.4f m  Ey %.4f m  Theta %.4f rad\n", *(float *)&Ex, *(float *)&Ey, *(float *)&Theta
end
document pose
The firmware's pose estimate (the reference sketch's Ex, Ey, Theta floats).
end

define counts
  printf "Count1 %lu  Count2 %lu\n", (unsigned long)Count1, (unsigned long)Count2
end
document counts
The reference sketch's encoder counts (unsigned long, incremented by the INT0/INT1 ISRs).
end

define where
  info symbol $pc
  printf "pc 0x%04x (flash byte address)  sp 0x%x (gdb's data space: 0x800000 + the SRAM address)\n", $pc, $sp
end
document where
Which function the AVR is in, with its PC and stack pointer.
end
