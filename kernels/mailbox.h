#pragma once
// A per-query mailbox: the set of triangle ids a ray (or a packet) has already tested, so
// that a triangle referenced by several grid cells is tested once. Direct-mapped on a hash of
// the id; a collision evicts, which only costs a retest, so it never skips a triangle it has
// not seen.
#include <cstdint>
#include <cstring>

namespace foton::kern {

template <int Bits>
class Mailbox {
  public:
    Mailbox() { std::memset(slot_, 0xff, sizeof(slot_)); }
    // True when `id` was marked before; marks it otherwise.
    bool seen(uint32_t id) {
        uint32_t& s = slot_[(id * 2654435761u) >> (32 - Bits)];
        if (s == id) return true;
        s = id;
        return false;
    }

  private:
    uint32_t slot_[1u << Bits];
};

}  // namespace foton::kern
