/**
 * @file message_kind.hpp
 * @brief A message kind declared once (tag, channel, roles, fields by word with the range
 *        each decoder enforces), and the encoder, decoder and dispatch by tag that follow from it.
 *
 * A kind is a constexpr object built by kind<Msg>() from a KindInfo and its
 * fields; each field names the member of the message struct it carries, where
 * its bits sit and the raw range a decoder accepts. encode() writes exactly the
 * declared words (every bit not declared is zero), decode() refuses, writing
 * nothing, any words that are not that kind (size, tag, a field out of range,
 * the kind's cross-field rule), and dispatch() looks a received tag up once in a
 * receiver's table of handlers. The same declaration is read by the host to
 * write the message table of the docs. Doubles and 64-bit words travel as two
 * words, low first, so a message is reproduced bit for bit.
 *
 * Lives in fdir, the lowest layer whose messages it serves (the application's,
 * the health and the supervisor messages); udn's own messages keep their
 * hand-written codecs.
 */
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <span>
#include <tuple>
#include <type_traits>

namespace fdir::msg {

/** How a field's member travels. */
enum class Type : std::uint8_t {
  kU32,   ///< unsigned integer, `bits` wide at `shift` (32: the whole word)
  kI32,   ///< signed integer as its two's-complement bits (a whole word)
  kBool,  ///< 0 or 1 (its raw range may say so)
  kF32,   ///< a float's IEEE-754 bits (a double member is rounded to float)
  kF64,   ///< a double's bits over two words, low first
  kU64,   ///< 64 bits over two words, low first
  kZero,  ///< reserved bits: no member, zero when sent, refused when not zero
};

inline constexpr std::uint32_t kNoTag = 0U;  ///< an untagged layout (a record inside a message, the IMU sample)
inline constexpr std::uint32_t kNoChannel = 0xFFFF'FFFFU;
inline constexpr std::uint8_t kNoCount = 0xFFU;

/** One field as the docs and the generic code read it. */
struct FieldInfo {
  const char* name;
  Type type;
  std::uint8_t word;   ///< first word (in a group: from the element's first word)
  std::uint8_t shift;  ///< lowest bit in the word
  std::uint8_t bits;   ///< 1 .. 32 within the word; 64 for kF64 and kU64
  std::uint8_t count;  ///< elements of an array member, each words_of() apart (1: a scalar)
  bool in_group;       ///< one per element of the kind's group
  std::uint32_t min;   ///< raw range the decoder enforces (fields within one word)
  std::uint32_t max;
};

constexpr std::uint32_t words_of(const FieldInfo& f) noexcept { return f.bits == 64U ? 2U : 1U; }
constexpr std::uint32_t mask_of(const FieldInfo& f) noexcept {
  return f.bits >= 32U ? 0xFFFF'FFFFU : ((1U << f.bits) - 1U);
}
/** Whether a field's range is all its bits can hold (nothing for a decoder to refuse). */
constexpr bool full_range(const FieldInfo& f) noexcept {
  return f.bits == 64U || f.type == Type::kF32 || (f.min == 0U && f.max == mask_of(f));
}

/**
 * Words repeated after the header: `count` elements of `elem_words`, the count
 * read from the header field `count_field` (kNoCount: always `fixed_count`).
 * An element is either the kind's in_group fields or a record laid out by
 * another declaration (`record`, read by the receiver from the words).
 */
struct GroupInfo {
  std::uint8_t count_field = kNoCount;
  std::uint8_t fixed_count = 0U;
  std::uint8_t elem_words = 0U;  ///< 0: no group
  const char* record = nullptr;
};

/** A kind: tag, name, channel, sender and receiver roles (masks of the deployment's roles), size. */
struct KindInfo {
  std::uint32_t tag;      ///< word 0 (kNoTag: untagged, word 0 is a field)
  const char* name;
  std::uint32_t channel;  ///< kNoChannel: a record inside other messages, or a channel the sender names (see routed())
  std::uint32_t from;     ///< senders' roles, a mask (bit = role number)
  std::uint32_t to;       ///< receivers' roles
  std::uint32_t words = 0U;  ///< fixed size; with a group, the header's (kind() computes it from the fields)
  GroupInfo group{};
  /** A rule over several fields, on the raw words (nullptr: none); `rule` says it for the docs. */
  bool (*check)(std::span<const std::uint32_t> w) noexcept = nullptr;
  const char* rule = "";
};

namespace detail {

template <typename V>
constexpr std::uint64_t to_raw(Type t, const V& v) noexcept {
  if constexpr (std::is_floating_point_v<V>) {
    return t == Type::kF32 ? std::uint64_t{std::bit_cast<std::uint32_t>(static_cast<float>(v))}
                           : std::bit_cast<std::uint64_t>(static_cast<double>(v));
  } else if constexpr (std::is_same_v<V, bool>) {
    return v ? 1U : 0U;
  } else if constexpr (std::is_enum_v<V>) {
    return static_cast<std::uint64_t>(static_cast<std::underlying_type_t<V>>(v));
  } else if constexpr (std::is_signed_v<V>) {
    return std::uint64_t{static_cast<std::uint32_t>(v)};
  } else {
    return static_cast<std::uint64_t>(v);
  }
}

template <typename V>
constexpr V from_raw(Type t, std::uint64_t raw) noexcept {
  if constexpr (std::is_floating_point_v<V>) {
    return t == Type::kF32 ? static_cast<V>(std::bit_cast<float>(static_cast<std::uint32_t>(raw)))
                           : static_cast<V>(std::bit_cast<double>(raw));
  } else if constexpr (std::is_same_v<V, bool>) {
    return raw != 0U;
  } else if constexpr (std::is_enum_v<V>) {
    return static_cast<V>(static_cast<std::underlying_type_t<V>>(raw));
  } else if constexpr (std::is_signed_v<V>) {
    return static_cast<V>(static_cast<std::int32_t>(static_cast<std::uint32_t>(raw)));
  } else {
    return static_cast<V>(raw);
  }
}

constexpr std::uint64_t read_raw(const FieldInfo& f, std::span<const std::uint32_t> w, std::size_t at) noexcept {
  if (f.bits == 64U) {
    return std::uint64_t{w[at]} | (std::uint64_t{w[at + 1U]} << 32U);
  }
  return (w[at] >> f.shift) & mask_of(f);
}

constexpr void write_raw(const FieldInfo& f, std::span<std::uint32_t> w, std::size_t at, std::uint64_t raw) noexcept {
  if (f.bits == 64U) {
    w[at] = static_cast<std::uint32_t>(raw);
    w[at + 1U] = static_cast<std::uint32_t>(raw >> 32U);
    return;
  }
  w[at] |= (static_cast<std::uint32_t>(raw) & mask_of(f)) << f.shift;
}

/** Word of element @p k of @p f: array elements are consecutive, group elements one group element apart. */
constexpr std::size_t word_at(const FieldInfo& f, const KindInfo& k, std::size_t e) noexcept {
  return f.in_group ? k.words + e * k.group.elem_words + f.word : f.word + e * words_of(f);
}

/** Elements of @p f in a message whose group has @p count elements. */
constexpr std::size_t elements(const FieldInfo& f, std::size_t count) noexcept {
  return f.in_group ? count : f.count;
}

}  // namespace detail

/** A field carrying member @p member (an array: one element per `count`) of Msg. */
template <typename Msg, typename M>
struct Field {
  using Message = Msg;
  FieldInfo info;
  M Msg::*member;

  static constexpr auto& at(Msg& m, M Msg::*p, std::size_t e) noexcept {
    if constexpr (std::is_array_v<M>) {
      return (m.*p)[e];
    } else {
      return m.*p;
    }
  }
  static constexpr const auto& at(const Msg& m, M Msg::*p, std::size_t e) noexcept {
    if constexpr (std::is_array_v<M>) {
      return (m.*p)[e];
    } else {
      return m.*p;
    }
  }
  constexpr void put(const KindInfo& k, const Msg& m, std::span<std::uint32_t> w, std::size_t count) const noexcept {
    for (std::size_t e = 0; e < detail::elements(info, count); ++e) {
      detail::write_raw(info, w, detail::word_at(info, k, e), detail::to_raw(info.type, at(m, member, e)));
    }
  }
  constexpr void get(const KindInfo& k, std::span<const std::uint32_t> w, std::size_t count, Msg& m) const noexcept {
    using V = std::remove_cvref_t<decltype(at(m, member, 0U))>;
    const std::size_t n = info.in_group ? std::extent_v<M> : info.count;
    for (std::size_t e = 0; e < n; ++e) {
      const std::uint64_t raw = e < detail::elements(info, count) ? detail::read_raw(info, w, detail::word_at(info, k, e)) : 0U;
      at(m, member, e) = detail::from_raw<V>(info.type, raw);
    }
  }
};

/** Reserved bits of a message: zero when sent, the words refused when they are not. */
template <typename Msg>
struct Zero {
  using Message = Msg;
  FieldInfo info;
  constexpr void put(const KindInfo& /*k*/, const Msg& /*m*/, std::span<std::uint32_t> /*w*/, std::size_t /*count*/) const noexcept {}
  constexpr void get(const KindInfo& /*k*/, std::span<const std::uint32_t> /*w*/, std::size_t /*count*/, Msg& /*m*/) const noexcept {}
};

// ---------------------------------------------------------------- field declarations

namespace detail {
template <typename M>
constexpr std::uint8_t extent_of() noexcept {
  return static_cast<std::uint8_t>(std::is_array_v<M> ? std::extent_v<M> : 1U);
}
}  // namespace detail

/** A whole word, unsigned, raw range min .. max. */
template <typename Msg, typename M>
constexpr Field<Msg, M> u32(const char* name, M Msg::*m, std::uint8_t word, std::uint32_t min = 0U,
                            std::uint32_t max = 0xFFFF'FFFFU) noexcept {
  return {{name, Type::kU32, word, 0U, 32U, detail::extent_of<M>(), false, min, max}, m};
}
/** A whole word, a signed member as its bits; the raw range as unsigned (0 .. INT32_MAX: not negative). */
template <typename Msg, typename M>
constexpr Field<Msg, M> i32(const char* name, M Msg::*m, std::uint8_t word, std::uint32_t min = 0U,
                            std::uint32_t max = 0xFFFF'FFFFU) noexcept {
  return {{name, Type::kI32, word, 0U, 32U, detail::extent_of<M>(), false, min, max}, m};
}
/** @p width bits from bit @p shift of word @p word, raw range min .. max (default: any). */
template <typename Msg, typename M>
constexpr Field<Msg, M> bits(const char* name, M Msg::*m, std::uint8_t word, std::uint8_t shift, std::uint8_t width,
                             std::uint32_t min = 0U, std::uint32_t max = 0xFFFF'FFFFU) noexcept {
  const std::uint32_t all = width >= 32U ? 0xFFFF'FFFFU : ((1U << width) - 1U);
  return {{name, std::is_same_v<M, bool> ? Type::kBool : Type::kU32, word, shift, width, detail::extent_of<M>(),
           false, min, max < all ? max : all},
          m};
}
/** A double (or each of an array's first @p count doubles), two words each. */
template <typename Msg, typename M>
constexpr Field<Msg, M> f64(const char* name, M Msg::*m, std::uint8_t word,
                            std::uint8_t count = detail::extent_of<M>()) noexcept {
  return {{name, Type::kF64, word, 0U, 64U, count, false, 0U, 0U}, m};
}
/** A float's bits in one word. */
template <typename Msg, typename M>
constexpr Field<Msg, M> f32(const char* name, M Msg::*m, std::uint8_t word) noexcept {
  return {{name, Type::kF32, word, 0U, 32U, 1U, false, 0U, 0xFFFF'FFFFU}, m};
}
/** 64 bits over two words, low first. */
template <typename Msg, typename M>
constexpr Field<Msg, M> u64(const char* name, M Msg::*m, std::uint8_t word) noexcept {
  return {{name, Type::kU64, word, 0U, 64U, 1U, false, 0U, 0U}, m};
}
/** Reserved bits that must be zero. */
template <typename Msg>
constexpr Zero<Msg> zero(std::uint8_t word, std::uint8_t shift, std::uint8_t width) noexcept {
  return {{"reserved", Type::kZero, word, shift, width, 1U, false, 0U, 0U}};
}
/** Bits of each group element (member: an array with one entry per element). */
template <typename Msg, typename M>
constexpr Field<Msg, M> each(const char* name, M Msg::*m, std::uint8_t word, std::uint8_t shift, std::uint8_t width) noexcept {
  const std::uint32_t all = width >= 32U ? 0xFFFF'FFFFU : ((1U << width) - 1U);
  return {{name, Type::kU32, word, shift, width, 1U, true, 0U, all}, m};
}

// ---------------------------------------------------------------- kinds

/** A declared kind: its KindInfo and its fields (as a tuple, and as FieldInfo rows). */
template <typename Msg, typename... F>
struct Kind {
  using Message = Msg;
  KindInfo info;
  std::tuple<F...> fields;
  std::array<FieldInfo, sizeof...(F)> rows;
};

/** Declares a kind of message Msg: @p info (its words are the header the fields cover) and its fields. */
template <typename Msg, typename... F>
constexpr Kind<Msg, F...> kind(KindInfo info, F... f) noexcept {
  static_assert((std::is_same_v<typename F::Message, Msg> && ...), "every field is of the kind's message");
  std::uint32_t end = info.tag == kNoTag ? 0U : 1U;
  const auto extend = [&end](const FieldInfo& x) {
    const std::uint32_t last = x.word + std::uint32_t{x.count} * words_of(x);
    end = x.in_group || last < end ? end : last;
  };
  (extend(f.info), ...);
  info.words = end;
  return {info, std::tuple<F...>{f...}, {f.info...}};
}

/**
 * Kind @p k as a deployment routes it: the same tag, name, fields and rule, on
 * @p channel from roles @p from to roles @p to. A lower layer declares its
 * messages without the roles of a deployment it cannot know; the deployment
 * lists them (its docs' table, its handlers' checks) through this.
 */
template <typename Msg, typename... F>
constexpr Kind<Msg, F...> routed(const Kind<Msg, F...>& k, std::uint32_t channel, std::uint32_t from,
                                 std::uint32_t to) noexcept {
  Kind<Msg, F...> r = k;
  r.info.channel = channel;
  r.info.from = from;
  r.info.to = to;
  return r;
}

/** What the docs, the tests and the dispatch checks read of any kind. */
struct KindView {
  const KindInfo* info;
  std::span<const FieldInfo> fields;
};
template <typename K>
constexpr KindView view(const K& k) noexcept {
  return {&k.info, std::span<const FieldInfo>(k.rows)};
}

/** Elements of the group of @p k in @p w (header already long enough); 0 without a group. */
constexpr std::uint32_t group_count(const KindView& k, std::span<const std::uint32_t> w) noexcept {
  const GroupInfo& g = k.info->group;
  if (g.elem_words == 0U) {
    return 0U;
  }
  if (g.count_field == kNoCount) {
    return g.fixed_count;
  }
  const FieldInfo& f = k.fields[g.count_field];
  return static_cast<std::uint32_t>(detail::read_raw(f, w, f.word));
}

/** Words of a message of @p k with @p count group elements. */
constexpr std::size_t words_with(const KindInfo& k, std::uint32_t count) noexcept {
  return std::size_t{k.words} + std::size_t{count} * k.group.elem_words;
}

/** Whether @p w is a message of kind @p k: size, tag, every field's raw range, the kind's rule. */
constexpr bool valid(const KindView& k, std::span<const std::uint32_t> w) noexcept {
  const KindInfo& i = *k.info;
  if (w.size() < i.words || w.empty() || (i.tag != kNoTag && w[0] != i.tag)) {
    return false;
  }
  const std::uint32_t count = group_count(k, w);
  const bool counted = i.group.count_field == kNoCount || count <= k.fields[i.group.count_field].max;
  if (!counted || w.size() != words_with(i, count)) {
    return false;
  }
  for (const FieldInfo& f : k.fields) {
    for (std::size_t e = 0; e < detail::elements(f, count) && !full_range(f); ++e) {
      const std::uint64_t raw = detail::read_raw(f, w, detail::word_at(f, i, e));
      if (raw < f.min || raw > f.max) {
        return false;
      }
    }
  }
  return i.check == nullptr || i.check(w);
}

/**
 * Writes a message of @p k from @p m into @p w: the header, and the group's
 * elements when they are the kind's fields (the count read from the header,
 * at most the count field's max). Returns the words of the message (header plus
 * group); when the elements are records the caller writes them (before or after).
 * Pre: @p w holds that many words.
 */
template <typename Msg, typename... F>
constexpr std::size_t encode(const Kind<Msg, F...>& k, const Msg& m, std::span<std::uint32_t> w) noexcept {
  std::fill(w.begin(), w.begin() + static_cast<std::ptrdiff_t>(k.info.words), 0U);
  if (k.info.tag != kNoTag) {
    w[0] = k.info.tag;
  }
  std::apply([&](const auto&... f) { (f.put(k.info, m, w, 0U), ...); }, k.fields);
  std::uint32_t count = group_count(view(k), w);
  const GroupInfo& g = k.info.group;
  if (g.count_field != kNoCount) {
    count = std::min(count, k.rows[g.count_field].max);
  }
  const std::size_t n = words_with(k.info, count);
  if (g.record == nullptr) {  // records are the caller's to write (they may already be there)
    std::fill(w.begin() + static_cast<std::ptrdiff_t>(k.info.words), w.begin() + static_cast<std::ptrdiff_t>(n), 0U);
    std::apply([&](const auto&... f) { ((f.info.in_group ? f.put(k.info, m, w, count) : void()), ...); }, k.fields);
  }
  return n;
}

/** Reads the fields of @p k from words this tile trusts (its own records): no checks. Pre: @p w is that long. */
template <typename Msg, typename... F>
constexpr Msg read(const Kind<Msg, F...>& k, std::span<const std::uint32_t> w) noexcept {
  Msg m{};
  const std::uint32_t count = group_count(view(k), w);
  std::apply([&](const auto&... f) { (f.get(k.info, w, count, m), ...); }, k.fields);
  return m;
}

/** Decodes @p w into @p out when it is a message of @p k (valid()); otherwise false, @p out untouched. */
template <typename Msg, typename... F>
[[nodiscard]] constexpr bool decode(const Kind<Msg, F...>& k, std::span<const std::uint32_t> w, Msg& out) noexcept {
  if (!valid(view(k), w)) {
    return false;
  }
  out = read(k, w);
  return true;
}

// ---------------------------------------------------------------- dispatch by tag

/** A receiver's handler of one kind: decodes and acts; false when it refused the words. */
template <typename Ctx>
struct Handler {
  const KindInfo* kind;
  bool (*take)(Ctx& c, std::span<const std::uint32_t> w) noexcept;
};

/** A handler that decodes kind @p K and hands the message to @p Fn(Ctx&, const Msg&). */
template <const auto& K, auto Fn, typename Ctx>
bool take(Ctx& c, std::span<const std::uint32_t> w) noexcept {
  typename std::remove_cvref_t<decltype(K)>::Message m{};
  if (!decode(K, w, m)) {
    return false;
  }
  Fn(c, m);
  return true;
}
template <const auto& K, auto Fn, typename Ctx>
constexpr Handler<Ctx> on() noexcept {
  return {&K.info, &take<K, Fn, Ctx>};
}

enum class Dispatch : std::uint8_t {
  kTaken,    ///< a handler took it
  kUnknown,  ///< no handler for its tag (or no words)
  kRefused,  ///< its kind's decoder refused it (size, range, rule)
};

/** Looks the tag (word 0) of @p w up in @p table once and hands the words to that kind's handler. */
template <typename Ctx, std::size_t N>
[[nodiscard]] Dispatch dispatch(const std::array<Handler<Ctx>, N>& table, std::span<const std::uint32_t> w, Ctx& c) noexcept {
  if (w.empty()) {
    return Dispatch::kUnknown;
  }
  for (const Handler<Ctx>& h : table) {
    if (h.kind->tag == w[0]) {
      return h.take(c, w) ? Dispatch::kTaken : Dispatch::kRefused;
    }
  }
  return Dispatch::kUnknown;
}

/**
 * dispatch() on a channel that also carries one untagged kind (the IMU samples among the
 * telecommands): words whose word 0 is no tag of @p table are that kind's, handed to @p untagged.
 * Words whose word 0 is a tag of @p table are that kind's and nothing else's.
 */
template <typename Ctx, std::size_t N>
[[nodiscard]] Dispatch dispatch(const std::array<Handler<Ctx>, N>& table, const Handler<Ctx>& untagged,
                                std::span<const std::uint32_t> w, Ctx& c) noexcept {
  const Dispatch d = dispatch(table, w, c);
  if (d != Dispatch::kUnknown || w.empty()) {
    return d;
  }
  return untagged.take(c, w) ? Dispatch::kTaken : Dispatch::kRefused;
}

/** Whether @p untagged takes the untagged kind of @p channel received by a role of @p to. */
template <typename Ctx>
constexpr bool untagged_fits(const Handler<Ctx>& untagged, std::uint32_t channel, std::uint32_t to) noexcept {
  return untagged.kind->tag == kNoTag && untagged.kind->channel == channel && (untagged.kind->to & to) != 0U;
}

/** Whether every handler of @p table takes a kind of @p channel received by a role of @p to, no tag twice. */
template <typename Ctx, std::size_t N>
constexpr bool handlers_fit(const std::array<Handler<Ctx>, N>& table, std::uint32_t channel, std::uint32_t to) noexcept {
  for (std::size_t i = 0; i < N; ++i) {
    if (table[i].kind->channel != channel || (table[i].kind->to & to) == 0U) {
      return false;
    }
    for (std::size_t j = i + 1U; j < N; ++j) {
      if (table[j].kind->tag == table[i].kind->tag) {
        return false;
      }
    }
  }
  return true;
}

}  // namespace fdir::msg
