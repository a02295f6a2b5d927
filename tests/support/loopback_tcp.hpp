#pragma once
// Loopback TCP helpers for the gdb tests: a free port, and which local
// addresses listen on a port as the kernel reports them (/proc/net/tcp and
// /proc/net/tcp6), to check that a listener is bound to 127.0.0.1 only.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace ddmr::test {

/// /proc/net/tcp's spelling of 127.0.0.1 (host byte order of a little-endian
/// machine, as the kernel prints it).
inline constexpr const char* kProcLoopback = "0100007F";

/// A port nobody listens on now (the kernel's pick for 127.0.0.1:0).
inline uint16_t free_loopback_port() {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t len = sizeof addr;
    if (fd < 0 || ::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 ||
        ::getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len) != 0) {
        if (fd >= 0) ::close(fd);
        return 0;
    }
    ::close(fd);
    return ntohs(addr.sin_port);
}

/// Local addresses (hex, as /proc/net/tcp* print them) of the sockets in
/// LISTEN state on `port`, IPv4 and IPv6.
inline std::vector<std::string> listening_addresses(uint16_t port) {
    constexpr const char* kListenState = "0A";
    char port_hex[8];
    std::snprintf(port_hex, sizeof port_hex, "%04X", static_cast<unsigned>(port));
    std::vector<std::string> found;
    for (const char* table : {"/proc/net/tcp", "/proc/net/tcp6"}) {
        std::ifstream in(table);
        std::string line;
        std::getline(in, line);  // header
        while (std::getline(in, line)) {
            std::istringstream fields(line);
            std::string slot, local, remote, state;
            fields >> slot >> local >> remote >> state;
            const auto colon = local.rfind(':');
            if (state == kListenState && colon != std::string::npos && local.substr(colon + 1) == port_hex) {
                found.push_back(local.substr(0, colon));
            }
        }
    }
    return found;
}

/// Polls until something listens on `port`, for at most `limit`.
inline bool wait_for_listener(uint16_t port, std::chrono::milliseconds limit) {
    const auto deadline = std::chrono::steady_clock::now() + limit;
    while (std::chrono::steady_clock::now() < deadline) {
        if (!listening_addresses(port).empty()) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return false;
}

}  // namespace ddmr::test
