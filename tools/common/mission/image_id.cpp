/**
 * @file image_id.cpp
 * @brief The GNU build ID of an ELF file, read from its program headers' notes (see image_id.hpp).
 */
#include "tools/common/mission/image_id.hpp"

#include <elf.h>

#include <array>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <vector>

namespace tools {

namespace {

namespace fs = std::filesystem;

/** Notes read at most per segment (a build ID note is 36 bytes; a segment holds a few). */
constexpr std::uint64_t kMaxNoteBytes = 4096U;

template <typename T>
bool read_at(std::ifstream& in, std::uint64_t offset, T& out) {
  in.seekg(static_cast<std::streamoff>(offset));
  return static_cast<bool>(in.read(reinterpret_cast<char*>(&out), sizeof out));  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): raw file bytes
}

std::string hex(const unsigned char* p, std::size_t n) {
  std::string s;
  std::array<char, 3> b{};
  for (std::size_t i = 0; i < n; ++i) {
    (void)std::snprintf(b.data(), b.size(), "%02x", p[i]);
    s += b.data();
  }
  return s;
}

/** The build ID in the notes @p bytes hold, or "". */
std::string build_id_in(const std::vector<unsigned char>& bytes) {
  std::size_t at = 0;
  while (at + sizeof(Elf64_Nhdr) <= bytes.size()) {
    Elf64_Nhdr h{};
    std::memcpy(&h, bytes.data() + at, sizeof h);
    const std::size_t name = at + sizeof h;
    const std::size_t desc = name + ((h.n_namesz + 3U) & ~std::size_t{3});
    const std::size_t next = desc + ((h.n_descsz + 3U) & ~std::size_t{3});
    if (next > bytes.size() || next <= at) {
      return {};
    }
    if (h.n_type == NT_GNU_BUILD_ID && h.n_namesz == 4U && std::memcmp(bytes.data() + name, "GNU", 4) == 0 &&
        h.n_descsz > 0U) {
      return hex(bytes.data() + desc, h.n_descsz);
    }
    at = next;
  }
  return {};
}

/** The GNU build ID of a 64-bit little-endian ELF file, or "". */
std::string build_id(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  Elf64_Ehdr eh{};
  if (!in || !read_at(in, 0, eh) || std::memcmp(eh.e_ident, ELFMAG, SELFMAG) != 0 ||
      eh.e_ident[EI_CLASS] != ELFCLASS64 || eh.e_ident[EI_DATA] != ELFDATA2LSB || eh.e_phentsize != sizeof(Elf64_Phdr)) {
    return {};
  }
  for (std::uint32_t i = 0; i < eh.e_phnum; ++i) {
    Elf64_Phdr ph{};
    if (!read_at(in, eh.e_phoff + std::uint64_t{i} * sizeof ph, ph)) {
      return {};
    }
    if (ph.p_type != PT_NOTE || ph.p_filesz == 0U || ph.p_filesz > kMaxNoteBytes) {
      continue;
    }
    std::vector<unsigned char> notes(ph.p_filesz);
    in.seekg(static_cast<std::streamoff>(ph.p_offset));
    if (!in.read(reinterpret_cast<char*>(notes.data()), static_cast<std::streamsize>(notes.size()))) {  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): raw file bytes
      return {};
    }
    std::string id = build_id_in(notes);
    if (!id.empty()) {
      return id;
    }
  }
  return {};
}

}  // namespace

std::string image_identity(const std::string& path) {
  const std::string id = build_id(path);
  if (!id.empty()) {
    return "gnu-" + id;
  }
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) {
    return {};
  }
  const auto t = fs::last_write_time(path, ec);
  return ec ? std::string{} : std::to_string(size) + "@" + std::to_string(t.time_since_epoch().count());
}

std::string own_image_identity() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string{} : image_identity(exe.string());
}

}  // namespace tools
