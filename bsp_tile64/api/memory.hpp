/**
 * @file memory.hpp
 * @brief The board's memory map: per-tile RAM regions and the shared DDR region.
 *
 * Both regions are static arrays placed by the linker fragment
 * (linker/host_memory.ld.S) in their own NOLOAD sections. Software obtains
 * memory from them only by carving at init: a carve is a bump allocation
 * inside one region, recorded by name for the size report. Nothing is ever
 * returned; a tile restart resets its own region and carves again.
 */
#pragma once

#include "linker/memory_config.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <new>
#include <span>
#include <type_traits>

namespace bsp {

inline constexpr std::uint32_t kMaxTiles = MEM_MAX_TILES;
inline constexpr std::size_t kTileRamBytes = MEM_TILE_RAM_BYTES;
inline constexpr std::size_t kDdrBytes = MEM_DDR_BYTES;
inline constexpr std::size_t kRegionAlign = MEM_REGION_ALIGN;
/** Carve records kept per region for the size report. */
inline constexpr std::size_t kMaxCarvesPerRegion = 48;

static_assert(kTileRamBytes % kRegionAlign == 0, "tile RAM must be a whole number of pages");
static_assert(kDdrBytes % kRegionAlign == 0, "DDR must be a whole number of pages");

enum class MemError : std::uint8_t {
  kOk,
  kBadRegion,  ///< tile index out of range
  kBadAlign,   ///< alignment not a power of two, or larger than a page
  kExhausted,  ///< the region has not enough free bytes left
  kTooMany,    ///< more carves than kMaxCarvesPerRegion
  kBadLayout,  ///< a control layout that does not describe the carved type
};

/** Result of a carve: a pointer into the region, or an error and nullptr. */
struct Carve {
  std::byte* ptr;
  MemError error;
};

/**
 * What a carve holds, as far as an upset of it can be modelled. The emulator
 * runs on the contexts' stacks and follows the host addresses kept in control
 * data (task control blocks, the messaging endpoint, a role's state with
 * pointers): a flipped bit there would crash the emulator, not model the tile.
 */
enum class CarveUse : std::uint8_t {
  kData,     ///< values only: an upset flips the bit
  kStack,    ///< a context's stack: random upsets leave it alone
  kControl,  ///< holds host addresses: an upset of one is modelled as a crash of the tile (ControlLayout)
};

struct ControlLayout;

/**
 * One member of a control struct: where it is and which of its bits are the
 * emulated tile's own state. Host state is what the host process follows or
 * runs on (a pointer, a view made of a pointer and its extent, a saved host
 * context): an upset of it is modelled as a crash of the tile. Emulated state
 * (counters, sequence numbers, indices, flags, tile ids, timers) is flipped
 * for real and the flight code must survive it. A bool's bits 1-7 are host
 * state too: a bool that is neither 0 nor 1 is undefined behaviour of the
 * host program, not a value the tile's software could read.
 */
struct ControlField {
  std::size_t offset;
  std::size_t bytes;
  std::size_t align;
  std::uint8_t live_bits;  ///< bits of each byte that are emulated state (0: host state)
  bool plain;              ///< arithmetic, enum, or arrays of them: no pointer, no struct inside
  const ControlLayout* inner = nullptr;  ///< a struct member, or an array of them, laid out by its own layout
};

namespace detail {
/** The element type under any nesting of std::array and built-in arrays. */
template <class X>
struct element_of {
  using type = std::remove_all_extents_t<X>;
};
template <class X, std::size_t N>
struct element_of<std::array<X, N>> {
  using type = typename element_of<X>::type;
};
template <class X>
using element_t = typename element_of<std::remove_cv_t<X>>::type;
template <class X>
inline constexpr bool kPlain = std::is_arithmetic_v<element_t<X>> || std::is_enum_v<element_t<X>>;
/** A member's size by its type: a pointer member's too (sizeof of a pointer expression reads as a mistake). */
template <class X>
inline constexpr std::size_t kSizeOf = sizeof(X);
template <class X>
inline constexpr std::uint8_t kLiveBits = std::is_same_v<element_t<X>, bool> ? 0x01U : 0xFFU;
}  // namespace detail

/**
 * Declares member @p m of control struct @p T as emulated state: a number,
 * an enum with its underlying type, a bool, or arrays of them (a struct
 * member is BSP_CONTROL_NESTED, a pointer BSP_CONTROL_HOST; control_layout_ok
 * refuses anything else here).
 */
#define BSP_CONTROL_STATE(T, m)                                                                               \
  ::bsp::ControlField {                                                                                       \
    offsetof(T, m), sizeof(T::m), alignof(decltype(T::m)), ::bsp::detail::kLiveBits<decltype(T::m)>,           \
        ::bsp::detail::kPlain<decltype(T::m)>, nullptr                                                        \
  }
/** Declares member @p m of control struct @p T as host state (any type). */
#define BSP_CONTROL_HOST(T, m) \
  ::bsp::ControlField { offsetof(T, m), ::bsp::detail::kSizeOf<decltype(T::m)>, alignof(decltype(T::m)), 0U, false, nullptr }
/** Declares member @p m of @p T, a struct or an array of structs, as laid out by @p layout (a ControlLayout). */
#define BSP_CONTROL_NESTED(T, m, layout) \
  ::bsp::ControlField { offsetof(T, m), sizeof(T::m), alignof(decltype(T::m)), 0xFFU, false, &(layout) }

/**
 * The layout of a control struct: every member, in declaration order.
 * Declared beside the struct, checked by control_layout_ok() in a
 * static_assert, recorded with its carve (carve_control_array) for the fault
 * injector, which flips a bit of emulated state for real and models an upset
 * of host state as a crash of the tile.
 */
struct ControlLayout {
  std::span<const ControlField> fields;
  std::size_t bytes;  ///< sizeof the struct
  std::size_t align;  ///< alignof the struct
};

/** Deepest nesting of layouts the injector follows (a struct in a struct in a carve's struct). */
inline constexpr std::uint32_t kControlDepth = 4U;

/**
 * True if @p l lists the members of its struct whole: in order, without
 * overlap, every gap shorter than the next member's alignment (padding, not a
 * member left out), the tail shorter than the struct's alignment; emulated
 * members plain (a pointer or a struct declared as plain state is refused),
 * nested ones a whole number of their layout's struct. A member added to the
 * struct and not to the list leaves a gap the check finds (unless it fits in
 * old padding). Nested layouts are checked by their own static_assert.
 */
constexpr bool control_layout_ok(const ControlLayout& l) noexcept {
  std::size_t end = 0U;
  for (const ControlField& f : l.fields) {
    const bool nested_ok = f.inner == nullptr || (f.inner->bytes != 0U && f.bytes % f.inner->bytes == 0U);
    const bool state_ok = f.inner != nullptr || f.live_bits == 0U || f.plain;
    if (f.offset < end || f.offset - end >= f.align || f.bytes == 0U || !nested_ok || !state_ok) {
      return false;
    }
    end = f.offset + f.bytes;
  }
  return end <= l.bytes && l.bytes - end < l.align;
}

/**
 * The bits of byte @p offset of a control carve laid out by @p l (one struct
 * after another) that are emulated state: 0 for host state, for any byte of
 * a carve whose layout is not declared (@p l nullptr), and below a nesting
 * deeper than kControlDepth. Padding between members is emulated RAM: 0xFF.
 */
constexpr std::uint8_t control_live_bits(const ControlLayout* l, std::size_t offset) noexcept {
  std::size_t at = offset;
  for (std::uint32_t depth = 0U; depth < kControlDepth; ++depth) {
    if (l == nullptr || l->bytes == 0U) {
      return 0U;
    }
    at %= l->bytes;
    const ControlField* hit = nullptr;
    for (const ControlField& f : l->fields) {
      hit = (at >= f.offset && at - f.offset < f.bytes) ? &f : hit;
    }
    if (hit == nullptr) {
      return 0xFFU;
    }
    if (hit->inner == nullptr) {
      return hit->live_bits;
    }
    at -= hit->offset;
    l = hit->inner;
  }
  return 0U;
}

/** True if bit @p bit of byte @p offset of a control carve laid out by @p l is host state (control_live_bits). */
constexpr bool control_bit_is_host(const ControlLayout* l, std::size_t offset, std::uint32_t bit) noexcept {
  return ((static_cast<std::uint32_t>(control_live_bits(l, offset)) >> (bit % 8U)) & 1U) == 0U;
}

/** One named carve, for the size report and the fault injector. */
struct CarveRecord {
  const char* what;  ///< static string naming the user
  std::size_t offset;
  std::size_t bytes;
  CarveUse use = CarveUse::kData;
  /** kControl: the layout of each element (nullptr: not declared, the whole carve is host state). */
  const ControlLayout* layout = nullptr;
};

/** Identifies a region: a tile's RAM, or the shared DDR. */
struct Region {
  static constexpr std::uint32_t kDdr = 0xFFFF'FFFFU;
  std::uint32_t id;  ///< tile index, or kDdr
};

/** Whole span of a region (carved or not). Empty span for a bad id. */
std::span<std::byte> region_span(Region r) noexcept;

/** Bytes carved so far in a region (0 for a bad id). */
std::size_t region_used(Region r) noexcept;

/**
 * Carves @p bytes aligned to @p align from region @p r.
 * @param what static string naming the user (kept by pointer for reports).
 * @return the pointer, or nullptr with the reason; the region is unchanged on error.
 * Memory is zeroed: a carve always starts from a known state.
 */
Carve carve(Region r, std::size_t bytes, std::size_t align, const char* what) noexcept;

/** carve() of a context's stack: recorded as one (CarveUse::kStack). */
Carve carve_stack(Region r, std::size_t bytes, std::size_t align, const char* what) noexcept;

/**
 * carve() of control data that holds host addresses (CarveUse::kControl).
 * @param layout the layout of its elements (static storage; nullptr: none
 *        declared, and an upset anywhere in it is modelled as a crash).
 */
Carve carve_control(Region r, std::size_t bytes, std::size_t align, const char* what,
                    const ControlLayout* layout = nullptr) noexcept;

/** Resets a region to empty (tile restart). The memory is zeroed. */
MemError region_reset(Region r) noexcept;

/** The carve records of a region; empty for a bad id. */
std::span<const CarveRecord> region_carves(Region r) noexcept;

/** Typed convenience over carve(): storage for @p count objects of T. */
template <class T>
T* carve_array(Region r, std::size_t count, const char* what, MemError* err) noexcept {
  const Carve c = carve(r, sizeof(T) * count, alignof(T), what);
  if (err != nullptr) {
    *err = c.error;
  }
  return reinterpret_cast<T*>(c.ptr);  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): raw region storage
}

/**
 * carve_array() of control data that holds host addresses (CarveUse::kControl).
 * @param layout T's layout (static storage, control_layout_ok), or nullptr: the
 *        whole carve is then host state. One not of T's size and alignment: kBadLayout.
 */
template <class T>
T* carve_control_array(Region r, std::size_t count, const char* what, MemError* err,
                       const ControlLayout* layout = nullptr) noexcept {
  if (layout != nullptr && (layout->bytes != sizeof(T) || layout->align != alignof(T))) {
    if (err != nullptr) {
      *err = MemError::kBadLayout;
    }
    return nullptr;
  }
  const Carve c = carve_control(r, sizeof(T) * count, alignof(T), what, layout);
  if (err != nullptr) {
    *err = c.error;
  }
  return reinterpret_cast<T*>(c.ptr);  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): raw region storage
}

/**
 * A record a task keeps in its tile's RAM for the host to read (its
 * telemetry: counters, modes): the carve's name and the record's layout,
 * declared once beside the record's type. The task carves it at start
 * (carve_record); the host finds it by this name among the tile's carves and
 * copies it out (tools/common/mission/ram_record.hpp), never through the task's code.
 * An upset of it flips the bit for real wherever the layout says emulated state.
 */
template <class T>
struct RamRecord {
  static_assert(std::is_trivially_copyable_v<T>, "a record is copied out of RAM byte for byte");
  const char* name;              ///< static string: the carve's name, unique among the tile's carves
  const ControlLayout* layout;   ///< T's layout (control_layout_ok), static storage
};

/**
 * Carves record @p rec in region @p r and value-initialises it (T{}).
 * @return the record, or nullptr with the reason in @p err (kBadLayout: the layout is not T's).
 */
template <class T>
T* carve_record(Region r, const RamRecord<T>& rec, MemError* err) noexcept {
  T* p = carve_control_array<T>(r, 1U, rec.name, err, rec.layout);
  if (p != nullptr) {
    ::new (static_cast<void*>(p)) T{};
  }
  return p;
}

/** Link-time bounds of the sections, from the linker fragment's symbols. */
struct SectionBounds {
  std::uintptr_t start;
  std::uintptr_t end;
  std::uintptr_t budget;
};
SectionBounds tile_ram_section() noexcept;
SectionBounds ddr_section() noexcept;

}  // namespace bsp
