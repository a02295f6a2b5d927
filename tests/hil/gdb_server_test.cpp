// GdbServer with a raw protocol client on another thread: it listens on
// 127.0.0.1 only and stops listening once gdb attached; registers and memory
// follow avr-gdb's layout (SREG kept consistent with simavr's split flags);
// step, continue, Ctrl-C (T02) and detach behave as gdb expects.
#include "hil/gdb_server.hpp"

#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/time.h>

#include <thread>

#include <sim_avr.h>

#include "support/loopback_tcp.hpp"
#include "support/test_paths.hpp"
#include "support/uno_board.hpp"

namespace ddmr::test {
namespace {

/// The gdb side of the protocol, minimal: acks every reply, no no-ack mode.
class RawGdbClient {
public:
    explicit RawGdbClient(uint16_t port) {
        fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
        timeval limit{10, 0};  // a missing reply fails the test instead of hanging it
        ::setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &limit, sizeof limit);
        sockaddr_in addr{};
        addr.sin_family = AF_INET;
        addr.sin_port = htons(port);
        addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        connected_ = ::connect(fd_, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) == 0;
    }
    ~RawGdbClient() { ::close(fd_); }
    RawGdbClient(const RawGdbClient&) = delete;
    RawGdbClient& operator=(const RawGdbClient&) = delete;

    bool connected() const { return connected_; }
    void send_bytes(const std::string& bytes) { ::send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL); }
    /// The next reply packet's payload ("<error>" on a timeout or a closed socket).
    std::string reply() {
        hil::rsp::PacketReader reader;
        for (;;) {
            char c = 0;
            if (::recv(fd_, &c, 1, 0) != 1) return "<error>";
            const auto event = reader.feed(c);
            if (event && event->kind == hil::rsp::Event::Kind::kPacket) {
                send_bytes("+");
                return event->payload;
            }
        }
    }
    std::string command(const std::string& packet) {
        send_bytes(hil::rsp::frame(packet));
        return reply();
    }

private:
    int fd_ = -1;
    bool connected_ = false;
};

TEST(GdbServer, ServesTheTargetOnLoopbackAndStopsOnCtrlC) {
    hil::AvrCore core(hil::ElfImage::read(firmware_elf()));
    const uint16_t port = free_loopback_port();
    ASSERT_NE(port, 0);
    hil::GdbServer server(core, {port, 30.0, 4096});
    // Bound at construction, to 127.0.0.1 only.
    EXPECT_EQ(listening_addresses(port), std::vector<std::string>{kProcLoopback});

    std::vector<std::string> listeners_after_attach{"<not read>"};
    std::string first_stop, g, sreg_in_memory, sram, step_stop, interrupt_stop, detach;
    std::thread client([&] {
        RawGdbClient gdb(port);
        if (!gdb.connected()) return;
        first_stop = gdb.command("?");
        listeners_after_attach = listening_addresses(port);
        g = gdb.command("g");
        gdb.command("P20=83");  // SREG = I | Z | C
        sreg_in_memory = gdb.command("m80005f,1");
        gdb.command("P20=00");
        gdb.command("M800200,2:a55a");
        sram = gdb.command("m800200,2");
        step_stop = gdb.command("s");
        // Continue and interrupt at once: the 0x03 may arrive with the 'c'.
        gdb.send_bytes(hil::rsp::frame("c") + "\x03");
        interrupt_stop = gdb.reply();
        detach = gdb.command("D");
    });
    server.wait_for_attach();  // returns at the client's first resume (its 's')
    EXPECT_TRUE(core.has_instruction_hooks());
    // Half a second of AVR time: far more than the client needs.
    core.run_until(hil::s_to_cycles(0.5, kUnoClockHz));
    client.join();

    EXPECT_EQ(first_stop.substr(0, 3), "T05");
    EXPECT_TRUE(listeners_after_attach.empty()) << listeners_after_attach.size();
    ASSERT_EQ(g.size(), 78u) << g;
    EXPECT_EQ(g.substr(70), "00000000");  // PC at the reset vector
    EXPECT_EQ(g.substr(66, 4), "ff08");   // simavr starts SP at RAMEND
    EXPECT_EQ(sreg_in_memory, "83");
    EXPECT_EQ(sram, "a55a");
    // The reset vector is a JMP: one step leaves address 0.
    EXPECT_EQ(step_stop.substr(0, 3), "T05");
    EXPECT_EQ(step_stop.find("22:00000000"), std::string::npos) << step_stop;
    EXPECT_EQ(interrupt_stop.substr(0, 3), "T02") << interrupt_stop;
    EXPECT_EQ(detach, "OK");
    EXPECT_FALSE(server.attached());
    server.release_if_detached();
    EXPECT_FALSE(core.has_instruction_hooks());
    EXPECT_GE(core.cycle(), hil::s_to_cycles(0.5, kUnoClockHz));
}

TEST(GdbServer, WritingSregSetsSimavrsSplitFlags) {
    hil::AvrCore core(hil::ElfImage::read(firmware_elf()));
    const uint16_t port = free_loopback_port();
    hil::GdbServer server(core, {port, 30.0, 4096});
    std::string reply;
    std::thread client([&] {
        RawGdbClient gdb(port);
        reply = gdb.command("M80005f,1:81");  // I and C through the data space
        gdb.command("D");
    });
    server.wait_for_attach();
    client.join();
    EXPECT_EQ(reply, "OK");
    const avr_t* avr = core.raw();
    EXPECT_EQ(avr->sreg[0], 1);  // C
    EXPECT_EQ(avr->sreg[1], 0);  // Z
    EXPECT_EQ(avr->sreg[7], 1);  // I
    EXPECT_EQ(avr->data[0x5F], 0x81);
}

TEST(GdbServer, NobodyAttachingIsAnError) {
    hil::AvrCore core(hil::ElfImage::read(firmware_elf()));
    const uint16_t port = free_loopback_port();
    hil::GdbServer server(core, {port, 0.05, 4096});
    try {
        server.wait_for_attach();
        FAIL() << "no error";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("no avr-gdb attached to 127.0.0.1:" + std::to_string(port)),
                  std::string::npos)
            << e.what();
    }
    EXPECT_FALSE(core.has_instruction_hooks());
}

TEST(GdbServer, APortInUseIsRefusedAtConstruction) {
    hil::AvrCore core(hil::ElfImage::read(firmware_elf()));
    const uint16_t port = free_loopback_port();
    hil::GdbServer first(core, {port, 30.0, 4096});
    try {
        hil::GdbServer second(core, {port, 30.0, 4096});
        FAIL() << "no error";
    } catch (const std::runtime_error& e) {
        EXPECT_EQ(std::string(e.what()), "--gdb " + std::to_string(port) + ": port " + std::to_string(port) +
                                             " on 127.0.0.1 is already in use");
    }
    EXPECT_THROW(hil::GdbServer(core, {0, 30.0, 4096}), std::invalid_argument);
}

}  // namespace
}  // namespace ddmr::test
