// GdbServer: avr-gdb's remote protocol on 127.0.0.1, on top of AvrCore's
// instruction hook (see gdb_server.hpp).
#include "hil/gdb_server.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <sim_avr.h>
#include <sim_core.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include <fmt/format.h>

#include "hil/eeprom_port.hpp"
#include "hil/machine_state.hpp"

namespace ddmr::hil {
namespace {

/// Largest memory read served in one 'm' reply [bytes]: its hex fits the
/// PacketSize advertised in qSupported.
constexpr uint64_t kMaxReadBytes = 2000;
constexpr const char* kSupported = "PacketSize=1000;QStartNoAckMode+";
/// avr-gdb talks to one inferior with one thread; this is its id.
constexpr const char* kThreadId = "1";
constexpr uint16_t kSregAddress = 0x5F;
constexpr uint16_t kSplAddress = 0x5D;
constexpr uint16_t kSphAddress = 0x5E;

std::string error_reply(int code) { return fmt::format("E{:02x}", code); }
constexpr int kErrBadArgs = 1;
constexpr int kErrBadAddress = 2;

bool starts_with(const std::string& s, std::string_view prefix) { return s.rfind(prefix, 0) == 0; }

}  // namespace

GdbServer::GdbServer(AvrCore& core, const GdbServerConfig& config) : core_(core), config_(config) {
    if (config_.port == 0) throw std::invalid_argument("--gdb 0: the port must be 1..65535");
    if (!(config_.attach_timeout_s > 0.0) || !std::isfinite(config_.attach_timeout_s)) {
        throw std::invalid_argument(fmt::format("gdb attach timeout {} s: must be > 0", config_.attach_timeout_s));
    }
    if (config_.interrupt_poll_instructions == 0) config_.interrupt_poll_instructions = 1;
    breakpoints_.assign(core_.raw()->flashend / 2U + 1U, false);

    listen_fd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (listen_fd_ < 0) {
        throw std::runtime_error(fmt::format("--gdb {}: cannot create a socket: {}", config_.port, std::strerror(errno)));
    }
    const int on = 1;
    ::setsockopt(listen_fd_, SOL_SOCKET, SO_REUSEADDR, &on, sizeof on);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(config_.port);
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);  // loopback only, never INADDR_ANY
    if (::bind(listen_fd_, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0 ||
        ::listen(listen_fd_, 1) != 0) {
        const int err = errno;
        ::close(listen_fd_);
        listen_fd_ = -1;
        throw std::runtime_error(err == EADDRINUSE
                                     ? fmt::format("--gdb {}: port {} on 127.0.0.1 is already in use",
                                                   config_.port, config_.port)
                                     : fmt::format("--gdb {}: cannot listen on 127.0.0.1:{}: {}", config_.port,
                                                   config_.port, std::strerror(err)));
    }
}

GdbServer::~GdbServer() {
    if (hook_installed_) core_.remove_instruction_hook(this);
    if (client_fd_ >= 0) ::close(client_fd_);
    if (listen_fd_ >= 0) ::close(listen_fd_);
}

void GdbServer::wait_for_attach() {
    if (state_ != State::kListening) throw std::logic_error("GdbServer::wait_for_attach called twice");
    using Clock = std::chrono::steady_clock;
    const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                             std::chrono::duration<double>(config_.attach_timeout_s));
    for (;;) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
        if (left <= 0) {
            throw std::runtime_error(fmt::format("--gdb {}: no avr-gdb attached to 127.0.0.1:{} within {} s",
                                                 config_.port, config_.port, config_.attach_timeout_s));
        }
        pollfd p{listen_fd_, POLLIN, 0};
        const int ready = ::poll(&p, 1, static_cast<int>(std::min<long long>(left, 1000)));
        if (ready < 0 && errno != EINTR) {
            throw std::runtime_error(fmt::format("--gdb {}: poll: {}", config_.port, std::strerror(errno)));
        }
        if (ready <= 0) continue;
        client_fd_ = ::accept4(listen_fd_, nullptr, nullptr, SOCK_CLOEXEC);
        if (client_fd_ >= 0) break;
        if (errno != EINTR && errno != ECONNABORTED) {
            throw std::runtime_error(fmt::format("--gdb {}: accept: {}", config_.port, std::strerror(errno)));
        }
    }
    ::close(listen_fd_);  // one client per run: no listener stays open
    listen_fd_ = -1;
    const int on = 1;
    ::setsockopt(client_fd_, IPPROTO_TCP, TCP_NODELAY, &on, sizeof on);
    state_ = State::kStopped;
    last_signal_ = rsp::kSigTrap;
    core_.add_instruction_hook(this, [this] { on_instruction(); });
    hook_installed_ = true;
    serve();
    release_if_detached();
}

void GdbServer::release_if_detached() {
    if (hook_installed_ && (state_ == State::kDetached || state_ == State::kKilled)) {
        core_.remove_instruction_hook(this);
        hook_installed_ = false;
    }
}

void GdbServer::end_of_run(int exit_code) {
    if (state_ == State::kRunning) {
        send_packet(fmt::format("W{:02x}", exit_code & 0xFF));
        drop_client(State::kDetached);
    } else if (state_ == State::kStopped) {
        drop_client(State::kDetached);
    }
    release_if_detached();
}

void GdbServer::on_instruction() {
    if (state_ != State::kRunning) {
        if (state_ == State::kKilled) core_.request_stop();
        return;
    }
    const std::size_t word = core_.raw()->pc / 2U;
    if (stepping_ || (breakpoint_count_ > 0 && word < breakpoints_.size() && breakpoints_[word])) {
        stop(rsp::kSigTrap);
        return;
    }
    if (++since_poll_ >= config_.interrupt_poll_instructions) {
        since_poll_ = 0;
        poll_for_interrupt();
    }
}

void GdbServer::stop(int signal) {
    stepping_ = false;
    last_signal_ = signal;
    state_ = State::kStopped;
    send_packet(rsp::stop_reply(signal, read_registers()));
    serve();
    if (state_ == State::kKilled) core_.request_stop();
}

void GdbServer::poll_for_interrupt() {
    std::string bytes;
    bytes.swap(pending_);
    char buf[256];
    for (;;) {
        const ssize_t n = ::recv(client_fd_, buf, sizeof buf, MSG_DONTWAIT);
        if (n > 0) {
            bytes.append(buf, static_cast<std::size_t>(n));
        } else if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
            break;  // nothing more now
        } else if (n == 0 || errno != EINTR) {
            drop_client(State::kDetached);  // the client went away: detach
            return;
        }
    }
    for (char c : bytes) {
        const auto event = reader_.feed(c);
        if (!event) continue;
        if (event->kind == rsp::Event::Kind::kInterrupt) {
            stop(rsp::kSigInt);
            return;
        }
        if (event->kind == rsp::Event::Kind::kNak && !last_packet_.empty()) send_raw(last_packet_);
    }
}

void GdbServer::serve() {
    if (!pending_.empty()) {
        std::string bytes;
        bytes.swap(pending_);
        if (consume(bytes.data(), bytes.size()) == Next::kLeave) return;
    }
    char buf[4096];
    while (state_ == State::kStopped) {
        const ssize_t n = ::recv(client_fd_, buf, sizeof buf, 0);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            drop_client(State::kDetached);
            return;
        }
        if (consume(buf, static_cast<std::size_t>(n)) == Next::kLeave) return;
    }
}

GdbServer::Next GdbServer::consume(const char* bytes, std::size_t count) {
    for (std::size_t i = 0; i < count; ++i) {
        const auto event = reader_.feed(bytes[i]);
        if (!event) continue;
        switch (event->kind) {
            case rsp::Event::Kind::kPacket:
                if (!no_ack_) send_raw("+");
                if (handle_packet(event->payload) == Next::kLeave) {
                    pending_.assign(bytes + i + 1, count - i - 1);
                    return Next::kLeave;
                }
                break;
            case rsp::Event::Kind::kBadChecksum:
                if (!no_ack_) send_raw("-");
                break;
            case rsp::Event::Kind::kNak:
                if (!last_packet_.empty()) send_raw(last_packet_);
                break;
            case rsp::Event::Kind::kAck:
            case rsp::Event::Kind::kInterrupt:  // already stopped
                break;
        }
        if (state_ != State::kStopped) return Next::kLeave;  // the connection failed
    }
    return Next::kStay;
}

GdbServer::Next GdbServer::handle_packet(const std::string& packet) {
    if (packet.empty()) {
        send_packet("");
        return Next::kStay;
    }
    const std::string args = packet.substr(1);
    switch (packet[0]) {
        case '?':
            send_packet(rsp::stop_reply(last_signal_, read_registers()));
            return Next::kStay;
        case 'g':
            send_packet(rsp::encode_registers(read_registers()));
            return Next::kStay;
        case 'G': {
            rsp::AvrRegisters regs;
            send_packet(write_registers_if(rsp::decode_registers(args, regs), regs));
            return Next::kStay;
        }
        case 'p': {
            const auto regno = rsp::parse_hex_number(args);
            const std::string value =
                regno && *regno < rsp::kRegisterCount
                    ? rsp::encode_register(read_registers(), static_cast<unsigned>(*regno))
                    : std::string();
            send_packet(value.empty() ? error_reply(kErrBadArgs) : value);
            return Next::kStay;
        }
        case 'P': {
            const auto eq = args.find('=');
            const auto regno = rsp::parse_hex_number(args.substr(0, eq));
            rsp::AvrRegisters regs = read_registers();
            const bool valid = eq != std::string::npos && regno && *regno < rsp::kRegisterCount &&
                               rsp::decode_register(static_cast<unsigned>(*regno), args.substr(eq + 1), regs);
            send_packet(write_registers_if(valid, regs));
            return Next::kStay;
        }
        case 'm': {
            const auto range = rsp::parse_memory_range(args);
            if (!range) {
                send_packet(error_reply(kErrBadArgs));
                return Next::kStay;
            }
            const std::string hex = read_memory(range->address, std::min(range->length, kMaxReadBytes));
            send_packet(hex.empty() && range->length > 0 ? error_reply(kErrBadAddress) : hex);
            return Next::kStay;
        }
        case 'M':
        case 'X': {
            const auto colon = args.find(':');
            const auto range = rsp::parse_memory_range(args.substr(0, colon));
            std::optional<std::vector<uint8_t>> bytes;
            if (colon != std::string::npos) {
                const std::string data = args.substr(colon + 1);
                bytes = packet[0] == 'M' ? rsp::from_hex(data) : std::vector<uint8_t>(data.begin(), data.end());
            }
            if (!range || !bytes || bytes->size() != range->length) {
                send_packet(error_reply(kErrBadArgs));
                return Next::kStay;
            }
            send_packet(bytes->empty() || write_memory(range->address, *bytes) ? "OK"
                                                                                : error_reply(kErrBadAddress));
            return Next::kStay;
        }
        case 'c':
            return resume(args, false);
        case 's':
            return resume(args, true);
        case 'Z':
            send_packet(set_breakpoint(args, true));
            return Next::kStay;
        case 'z':
            send_packet(set_breakpoint(args, false));
            return Next::kStay;
        case 'k':  // no reply: gdb does not wait for one
            drop_client(State::kKilled);
            return Next::kLeave;
        case 'D':
            send_packet("OK");
            drop_client(State::kDetached);
            return Next::kLeave;
        case 'H':
        case 'T':
            send_packet("OK");
            return Next::kStay;
        default:
            break;
    }
    if (starts_with(packet, "qSupported")) {
        send_packet(kSupported);
    } else if (packet == "QStartNoAckMode") {
        send_packet("OK");
        no_ack_ = true;
    } else if (packet == "qAttached") {
        send_packet("1");  // an existing process: gdb's quit detaches instead of killing
    } else if (packet == "qC") {
        send_packet(std::string("QC") + kThreadId);
    } else if (packet == "qfThreadInfo") {
        send_packet(std::string("m") + kThreadId);
    } else if (packet == "qsThreadInfo") {
        send_packet("l");
    } else if (starts_with(packet, "qSymbol")) {
        send_packet("OK");
    } else if (starts_with(packet, "vKill")) {
        send_packet("OK");
        drop_client(State::kKilled);
        return Next::kLeave;
    } else {
        send_packet("");  // not supported (vCont?, vMustReplyEmpty, Z2..Z4 go above)
    }
    return Next::kStay;
}

GdbServer::Next GdbServer::resume(const std::string& args, bool step) {
    if (!args.empty()) {
        const auto address = rsp::parse_hex_number(args);
        if (!address || *address >= rsp::kDataBase) {
            send_packet(error_reply(kErrBadArgs));
            return Next::kStay;
        }
        core_.raw()->pc = static_cast<uint32_t>(*address);
    }
    stepping_ = step;
    since_poll_ = 0;
    state_ = State::kRunning;
    return Next::kLeave;
}

std::string GdbServer::set_breakpoint(const std::string& args, bool insert) {
    const auto request = rsp::parse_breakpoint(args);
    if (!request) return error_reply(kErrBadArgs);
    if (request->type > 1) return "";  // watchpoints: gdb single-steps and compares instead
    const auto where = rsp::decode_address(request->address);
    if (!where || where->space != rsp::Space::kFlash || where->offset / 2U >= breakpoints_.size()) {
        return error_reply(kErrBadAddress);
    }
    const std::size_t word = where->offset / 2U;
    if (breakpoints_[word] != insert) {
        breakpoints_[word] = insert;
        if (insert) {
            ++breakpoint_count_;
        } else {
            --breakpoint_count_;
        }
    }
    return "OK";
}

void GdbServer::send_packet(const std::string& payload) {
    last_packet_ = rsp::frame(payload);
    send_raw(last_packet_);
}

void GdbServer::send_raw(const std::string& bytes) {
    if (client_fd_ < 0) return;
    std::size_t sent = 0;
    while (sent < bytes.size()) {
        const ssize_t n = ::send(client_fd_, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            drop_client(State::kDetached);
            return;
        }
        sent += static_cast<std::size_t>(n);
    }
}

void GdbServer::drop_client(State next) {
    if (client_fd_ >= 0) ::close(client_fd_);
    client_fd_ = -1;
    if (state_ != State::kKilled) state_ = next;
    stepping_ = false;
    if (state_ == State::kDetached) {
        // A detached target runs freely: nothing may stop it any more.
        std::fill(breakpoints_.begin(), breakpoints_.end(), false);
        breakpoint_count_ = 0;
    }
}

rsp::AvrRegisters GdbServer::read_registers() const {
    const avr_t* avr = core_.raw();
    rsp::AvrRegisters regs;
    std::copy(avr->data, avr->data + regs.r.size(), regs.r.begin());
    regs.sreg = sreg_of(avr);
    regs.sp = core_.stack_pointer();
    regs.pc = avr->pc;
    return regs;
}

void GdbServer::write_sreg(uint8_t value) {
    avr_t* avr = core_.raw();
    // simavr keeps SREG split in sreg[] (what instructions use) and rebuilds
    // data[SREG] only when the firmware reads it: set both.
    for (uint8_t bit = 0; bit < 8; ++bit) avr_sreg_set(avr, bit, static_cast<uint8_t>((static_cast<unsigned>(value) >> bit) & 1U));
    avr->data[kSregAddress] = value;
}

std::string GdbServer::write_registers_if(bool valid, const rsp::AvrRegisters& regs) {
    if (!valid) return error_reply(kErrBadArgs);
    write_registers(regs);
    return "OK";
}

void GdbServer::write_registers(const rsp::AvrRegisters& regs) {
    avr_t* avr = core_.raw();
    std::copy(regs.r.begin(), regs.r.end(), avr->data);
    write_sreg(regs.sreg);
    avr->data[kSplAddress] = static_cast<uint8_t>(regs.sp & 0xFFU);
    avr->data[kSphAddress] = static_cast<uint8_t>(regs.sp >> 8);
    avr->pc = regs.pc;
}

std::string GdbServer::read_memory(uint64_t address, uint64_t length) const {
    const auto where = rsp::decode_address(address);
    if (!where || length == 0) return {};
    const avr_t* avr = core_.raw();
    // Replies may be shorter than asked: serve the part inside the space.
    std::vector<uint8_t> out;
    switch (where->space) {
        case rsp::Space::kFlash: {
            const uint64_t end = std::min<uint64_t>(where->offset + length, avr->flashend + 1ULL);
            for (uint64_t a = where->offset; a < end; ++a) out.push_back(avr->flash[a]);
            break;
        }
        case rsp::Space::kData: {
            const uint64_t end = std::min<uint64_t>(where->offset + length, avr->ramend + 1ULL);
            for (uint64_t a = where->offset; a < end; ++a) out.push_back(avr->data[a]);
            if (where->offset <= kSregAddress && kSregAddress < end) {
                out[kSregAddress - where->offset] = sreg_of(avr);
            }
            break;
        }
        case rsp::Space::kEeprom: {
            const EepromImage image = EepromPort(core_).read_all();
            const uint64_t end = std::min<uint64_t>(where->offset + length, image.size());
            for (uint64_t a = where->offset; a < end; ++a) out.push_back(image[a]);
            break;
        }
    }
    return rsp::to_hex(out);
}

bool GdbServer::write_memory(uint64_t address, const std::vector<uint8_t>& bytes) {
    const auto where = rsp::decode_address(address);
    if (!where) return false;
    avr_t* avr = core_.raw();
    const uint64_t end = uint64_t{where->offset} + bytes.size();
    switch (where->space) {
        case rsp::Space::kFlash:
            if (end > avr->flashend + 1ULL) return false;
            std::copy(bytes.begin(), bytes.end(), avr->flash + where->offset);
            return true;
        case rsp::Space::kData:
            if (end > avr->ramend + 1ULL) return false;
            std::copy(bytes.begin(), bytes.end(), avr->data + where->offset);
            if (where->offset <= kSregAddress && kSregAddress < end) {
                write_sreg(bytes[kSregAddress - where->offset]);
            }
            return true;
        case rsp::Space::kEeprom: {
            EepromPort port(core_);
            EepromImage image = port.read_all();
            if (end > image.size()) return false;
            std::copy(bytes.begin(), bytes.end(), image.begin() + where->offset);
            port.preload(image);
            return true;
        }
    }
    return false;
}

}  // namespace ddmr::hil
