#pragma once
// One encoder edge as the plant reports it to the HIL, and a
// fixed-capacity, caller-owned buffer of them (no heap in the step loop).

#include <array>
#include <cstddef>
#include <cstdint>

namespace ddmr::plant {

struct EncoderEdge {
    unsigned channel = 0;  ///< the motor: 0: motor 1 (right wheel), 1: motor 2 (left wheel)
    double t_s = 0.0;      ///< exact plant time of the edge [s]
    bool level = false;    ///< the output's level after the edge
    unsigned signal = 0;   ///< which output changed: 0: A or OUT, 1: B (hall_encoder.hpp)
};

class EdgeBuffer {
  public:
    static constexpr std::size_t kCapacity = 256;

    /// Appends an edge; when full, counts it as dropped and returns false.
    bool push(const EncoderEdge& e) {
        if (size_ == kCapacity) {
            ++dropped_;
            return false;
        }
        edges_[size_++] = e;
        return true;
    }
    void clear() {
        size_ = 0;
        dropped_ = 0;
    }
    [[nodiscard]] std::size_t size() const { return size_; }
    [[nodiscard]] bool empty() const { return size_ == 0; }
    [[nodiscard]] std::uint64_t dropped() const { return dropped_; }
    [[nodiscard]] const EncoderEdge& operator[](std::size_t i) const { return edges_[i]; }
    [[nodiscard]] const EncoderEdge* begin() const { return edges_.data(); }
    [[nodiscard]] const EncoderEdge* end() const { return edges_.data() + size_; }
    /// Mutable access for sorting the edges of one step by time.
    [[nodiscard]] EncoderEdge* data() { return edges_.data(); }

  private:
    std::array<EncoderEdge, kCapacity> edges_{};
    std::size_t size_ = 0;
    std::uint64_t dropped_ = 0;
};

}  // namespace ddmr::plant
