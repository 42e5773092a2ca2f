/**
 * @file flight_rules.cpp
 * @brief Token-level checks of the flight-code rules.
 */
#include "tools/common/flight_rules.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <fstream>
#include <regex>
#include <sstream>

namespace tools::flight_rules {
namespace {

constexpr std::array<std::string_view, 5> kLayers = {"bsp_tile64", "kernel", "udn", "fdir", "trn"};

struct Token {
  std::string text;
  int line;
};

bool is_ident_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_'; }

/** Splits stripped source into identifier tokens and single punctuation characters. */
std::vector<Token> tokenize(const std::string& s) {
  std::vector<Token> out;
  int line = 1;
  for (std::size_t i = 0; i < s.size();) {
    const char c = s[i];
    if (c == '\n') {
      ++line;
      ++i;
    } else if (std::isspace(static_cast<unsigned char>(c)) != 0) {
      ++i;
    } else if (is_ident_char(c)) {
      std::size_t j = i;
      while (j < s.size() && is_ident_char(s[j])) {
        ++j;
      }
      out.push_back({s.substr(i, j - i), line});
      i = j;
    } else if (c == '-' && i + 1 < s.size() && s[i + 1] == '>') {
      out.push_back({"->", line});
      i += 2;
    } else if (c == ':' && i + 1 < s.size() && s[i + 1] == ':') {
      out.push_back({"::", line});
      i += 2;
    } else {
      out.push_back({std::string(1, c), line});
      ++i;
    }
  }
  return out;
}

const std::array<std::string_view, 9> kCAllocators = {"malloc", "calloc", "realloc", "free", "aligned_alloc",
                                                      "posix_memalign", "memalign", "strdup", "valloc"};
const std::array<std::string_view, 27> kHeapStd = {
    "vector", "string", "wstring", "function", "map", "multimap", "unordered_map", "unordered_multimap", "set",
    "multiset", "unordered_set", "list", "forward_list", "deque", "shared_ptr", "unique_ptr", "make_shared",
    "make_unique", "any", "stringstream", "ostringstream", "istringstream", "regex", "cout", "cerr",
    "queue", "priority_queue"};
const std::array<std::string_view, 8> kHostStd = {"thread", "mutex", "async", "random_device", "mt19937",
                                                  "mt19937_64", "default_random_engine", "chrono"};
const std::array<std::string_view, 16> kBannedHeaders = {
    "vector", "string", "map", "unordered_map", "set", "unordered_set", "list", "forward_list", "deque",
    "iostream", "sstream", "fstream", "thread", "random", "chrono", "regex"};

template <std::size_t N>
bool in(const std::array<std::string_view, N>& set, std::string_view w) {
  for (const std::string_view s : set) {
    if (s == w) {
      return true;
    }
  }
  return false;
}

void check_tokens(std::string_view file, const std::vector<Token>& t, std::vector<Finding>& out) {
  auto add = [&](int line, const char* rule, const std::string& msg) {
    out.push_back({std::string(file), line, rule, msg});
  };
  for (std::size_t i = 0; i < t.size(); ++i) {
    const std::string& w = t[i].text;
    const std::string prev = i > 0 ? t[i - 1].text : "";
    const std::string next = i + 1 < t.size() ? t[i + 1].text : "";
    const std::string prev2 = i > 1 ? t[i - 2].text : "";
    const int ln = t[i].line;
    if (w == "new" && prev != "operator" && next != "(") {
      add(ln, "heap", "'new' allocates from the heap; use static storage or a kernel pool");
    } else if (w == "delete" && prev != "operator" && prev != "=") {
      add(ln, "heap", "'delete' frees heap memory; flight code owns no heap memory");
    } else if (in(kCAllocators, w) && next == "(" && prev != "." && prev != "->" && prev != "operator") {
      add(ln, "heap", "'" + w + "' is heap allocation; use static storage");
    } else if (prev == "::" && prev2 == "std" && in(kHeapStd, w)) {
      add(ln, "heap", "'std::" + w + "' allocates or streams; use a fixed-capacity container");
    } else if (prev == "::" && prev2 == "std" && in(kHostStd, w)) {
      add(ln, "host-time", "'std::" + w + "' brings host time, threads or randomness into emulated behaviour");
    } else if (w == "throw" || w == "try" || w == "catch") {
      add(ln, "exceptions", "'" + w + "': flight code has no exceptions; return an error value");
    } else if (w == "dynamic_cast" || w == "typeid") {
      add(ln, "rtti", "'" + w + "' needs RTTI, which flight code does not have");
    } else if ((w == "rand" || w == "srand" || w == "gettimeofday" || w == "clock_gettime") && next == "(" &&
               prev != "." && prev != "->") {
      add(ln, "host-time", "'" + w + "' is host time or unseeded randomness; use the board's clock and streams");
    }
  }
}

void check_includes(std::string_view file, std::string_view text, std::string_view layer, bool host_side,
                    std::vector<Finding>& out) {
  static const std::regex kInclude(R"(^\s*#\s*include\s*([<"])([^>"]+)[>"])");
  const int rank = layer_rank(layer);
  std::istringstream in_text{std::string(text)};
  std::string line;
  int ln = 0;
  while (std::getline(in_text, line)) {
    ++ln;
    std::smatch m;
    if (!std::regex_search(line, m, kInclude)) {
      continue;
    }
    const std::string path = m[2].str();
    const std::string top = path.substr(0, path.find('/'));
    auto add = [&](const char* rule, const std::string& msg) {
      out.push_back({std::string(file), ln, rule, msg});
    };
    if (m[1].str() == "<" && !host_side && in(kBannedHeaders, path)) {
      add("heap", "<" + path + "> is not for flight code (heap, streams, host time or host randomness)");
    } else if (top == "tools" || top == "tests") {
      add("layering", "flight code includes host code '" + path + "'");
    } else if (layer_rank(top) > rank) {
      std::string msg = "'";
      msg.append(path).append("' is in layer ").append(top).append(", above ").append(layer);
      add("layering", msg);
    } else if (rank > 0 && path.rfind("bsp_tile64/world/", 0) == 0) {
      add("truth", "'" + path + "' is the world's truth; flight code sees only what devices report");
    }
  }
}

}  // namespace

int layer_rank(std::string_view layer) {
  for (std::size_t i = 0; i < kLayers.size(); ++i) {
    if (kLayers[i] == layer) {
      return static_cast<int>(i);
    }
  }
  return -1;
}

std::string layer_of(std::string_view path) {
  std::string p(path);
  if (p.rfind("./", 0) == 0) {
    p = p.substr(2);
  }
  const std::string top = p.substr(0, p.find('/'));
  return layer_rank(top) >= 0 ? top : std::string();
}

std::string strip_comments_and_literals(std::string_view text) {
  std::string s(text);
  enum class St { kCode, kLine, kBlock, kStr, kChr } st = St::kCode;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const char c = s[i];
    const char n = i + 1 < s.size() ? s[i + 1] : '\0';
    switch (st) {
      case St::kCode:
        if (c == '/' && n == '/') {
          st = St::kLine;
          s[i] = ' ';
        } else if (c == '/' && n == '*') {
          st = St::kBlock;
          s[i] = ' ';
        } else if (c == '"') {
          st = St::kStr;
        } else if (c == '\'' && (i == 0 || !std::isxdigit(static_cast<unsigned char>(s[i - 1])))) {
          st = St::kChr;  // a quote after a hex digit is a digit separator (0xFFFF'FFFF)
        }
        break;
      case St::kLine:
        if (c == '\n') {
          st = St::kCode;
        } else {
          s[i] = ' ';
        }
        break;
      case St::kBlock:
        if (c == '*' && n == '/') {
          s[i] = ' ';
          s[i + 1] = ' ';
          ++i;
          st = St::kCode;
        } else if (c != '\n') {
          s[i] = ' ';
        }
        break;
      case St::kStr:
      case St::kChr:
        if (c == '\\' && n != '\0') {
          s[i] = ' ';
          if (n != '\n') {
            s[i + 1] = ' ';
          }
          ++i;
        } else if ((st == St::kStr && c == '"') || (st == St::kChr && c == '\'')) {
          st = St::kCode;
        } else if (c != '\n') {
          s[i] = ' ';
        }
        break;
    }
  }
  return s;
}

std::vector<Finding> check_source(std::string_view file, std::string_view text, std::string_view layer,
                                  bool host_side) {
  std::vector<Finding> out;
  check_includes(file, text, layer, host_side, out);
  if (!host_side) {
    // Directives are checked by check_includes; blank them so <new> is not 'new'.
    std::string code = strip_comments_and_literals(text);
    std::size_t bol = 0;
    while (bol < code.size()) {
      std::size_t eol = code.find('\n', bol);
      eol = (eol == std::string::npos) ? code.size() : eol;
      const std::size_t first = code.find_first_not_of(" \t", bol);
      if (first < eol && code[first] == '#') {
        std::fill(code.begin() + static_cast<std::ptrdiff_t>(first), code.begin() + static_cast<std::ptrdiff_t>(eol), ' ');
      }
      bol = eol + 1;
    }
    check_tokens(file, tokenize(code), out);
  }
  return out;
}

std::vector<Finding> check_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) {
    return {{path, 0, "io", "cannot read file"}};
  }
  std::ostringstream ss;
  ss << in.rdbuf();
  const bool host_side = path.find("/host/") != std::string::npos;
  return check_source(path, ss.str(), layer_of(path), host_side);
}

}  // namespace tools::flight_rules
