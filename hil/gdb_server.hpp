#pragma once
// GdbServer: an avr-gdb remote target for one AvrCore, served on a TCP socket
// bound to 127.0.0.1 only (never simavr 1.6's own stub, avr_gdb_init, which
// binds every interface). One client per run; the listening socket is closed
// as soon as it has attached, so no network listener remains.
//
// Execution control: an AvrCore instruction hook runs after every
// instruction. While gdb has the target stopped, the hook blocks reading
// commands: the AVR and with it the plant (stepped by simavr cycle timers)
// stand still, so the robot stays coupled and consistent across a stop.
// Running under gdb single-steps simavr (one instruction per avr_run), which
// is several times slower than a run without it.
//
// Protocol: ? g G p P m M X c s (with an optional address) Z0/z0 Z1/z1
// (breakpoints: a flash-word bitmap checked in the hook) k D qSupported
// QStartNoAckMode qAttached qC qfThreadInfo/qsThreadInfo Hg/Hc T qSymbol;
// anything else (vCont?, watchpoints Z2..Z4, ...) gets the empty reply, so
// gdb falls back to what is listed. Ctrl-C (0x03) is polled every
// `interrupt_poll_instructions` without blocking. Memory reads take the data
// space from avr->data directly (no I/O read side effects); SREG is rebuilt
// from simavr's split sreg[] bits, and writes keep both consistent.
//
// Signals: none; it attaches to the core's instruction hooks (owner: this).
// Not thread-safe: use from the thread that runs the core.

#include <cstdint>
#include <string>
#include <vector>

#include "hil/avr_core.hpp"
#include "hil/gdb_rsp.hpp"

namespace ddmr::hil {

struct GdbServerConfig {
    uint16_t port = 0;  ///< TCP port on 127.0.0.1, 1..65535
    /// How long wait_for_attach() waits for avr-gdb [wall-clock s], > 0.
    /// Wall time only bounds the wait; it never enters the simulation.
    double attach_timeout_s = 300.0;
    /// Instructions between non-blocking checks for gdb's Ctrl-C while running.
    uint32_t interrupt_poll_instructions = 4096;
};

class GdbServer {
public:
    /// Binds and listens on 127.0.0.1:port at once, so a port in use is
    /// reported before anything else happens. Throws std::invalid_argument for
    /// port 0 and std::runtime_error ("--gdb PORT: ...") if the port cannot be
    /// bound.
    GdbServer(AvrCore& core, const GdbServerConfig& config);
    ~GdbServer();
    GdbServer(const GdbServer&) = delete;
    GdbServer& operator=(const GdbServer&) = delete;

    uint16_t port() const { return config_.port; }

    /// Waits for avr-gdb to connect (throws std::runtime_error after
    /// attach_timeout_s), closes the listener and serves the client with the
    /// CPU before its next instruction until gdb continues, steps, detaches
    /// or kills.
    void wait_for_attach();

    /// True once gdb has sent 'k': the caller ends the run (the hook also
    /// requests a stop of the running run_until).
    bool killed() const { return state_ == State::kKilled; }
    /// True while a client is connected.
    bool attached() const { return state_ == State::kRunning || state_ == State::kStopped; }

    /// After gdb detached or closed the connection: removes the instruction
    /// hook so the run goes on at full speed. Call between run_until calls
    /// (never from inside a hook).
    void release_if_detached();

    /// The firmware run is over: a client waiting for a stop reply is told the
    /// program exited with `exit_code` (W packet) and the connection closed.
    void end_of_run(int exit_code);

private:
    enum class State { kListening, kStopped, kRunning, kDetached, kKilled };
    enum class Next { kStay, kLeave };  ///< after a packet: keep serving, or leave the stop

    void on_instruction();
    void stop(int signal);
    /// Serves commands until one resumes, detaches or kills.
    void serve();
    /// Feeds received bytes to the reader; stores what follows a resume.
    Next consume(const char* bytes, std::size_t count);
    Next handle_packet(const std::string& packet);
    void poll_for_interrupt();
    void send_packet(const std::string& payload);
    void send_raw(const std::string& bytes);
    void drop_client(State next);

    rsp::AvrRegisters read_registers() const;
    void write_registers(const rsp::AvrRegisters& regs);
    /// 'G' and 'P': writes `regs` if the request was `valid`; the reply.
    std::string write_registers_if(bool valid, const rsp::AvrRegisters& regs);
    void write_sreg(uint8_t value);
    std::string read_memory(uint64_t address, uint64_t length) const;
    bool write_memory(uint64_t address, const std::vector<uint8_t>& bytes);
    Next resume(const std::string& args, bool step);
    std::string set_breakpoint(const std::string& args, bool insert);

    AvrCore& core_;
    GdbServerConfig config_;
    int listen_fd_ = -1;
    int client_fd_ = -1;
    State state_ = State::kListening;
    bool hook_installed_ = false;
    bool stepping_ = false;
    bool no_ack_ = false;
    int last_signal_ = rsp::kSigTrap;
    uint32_t since_poll_ = 0;
    rsp::PacketReader reader_;
    std::string pending_;      ///< bytes received after a resume, not yet consumed
    std::string last_packet_;  ///< for a resend on '-'
    std::vector<bool> breakpoints_;  ///< one per flash word
    std::size_t breakpoint_count_ = 0;
};

}  // namespace ddmr::hil
