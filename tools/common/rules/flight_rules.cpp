/**
 * @file flight_rules.cpp
 * @brief Token-level checks of the flight-code rules, the include rules and the include graph.
 */
#include "tools/common/rules/flight_rules.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>

namespace tools::flight_rules {
namespace {

/** Ranked folders, lowest first; tools and tests share the top rank. */
struct Layer {
  std::string_view name;
  int rank;
};
constexpr std::array<Layer, 7> kLayers = {{{"bsp_tile64", 0},
                                           {"kernel", 1},
                                           {"udn", 2},
                                           {"fdir", 3},
                                           {"trn", 4},
                                           {"tools", 5},
                                           {"tests", 5}}};
constexpr int kTopFlightRank = 4;
constexpr std::string_view kFixtures = "tests/fixtures/";

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

struct Include {
  int line;
  bool angled;
  std::string path;
};

/** The #include directives of a text, in order (line-based, as the preprocessor sees them). */
std::vector<Include> includes_of(std::string_view text) {
  static const std::regex kInclude(R"(^\s*#\s*include\s*([<"])([^>"]+)[>"])");
  std::vector<Include> out;
  std::istringstream in_text{std::string(text)};
  std::string line;
  int ln = 0;
  while (std::getline(in_text, line)) {
    ++ln;
    std::smatch m;
    if (std::regex_search(line, m, kInclude)) {
      out.push_back({ln, m[1].str() == "<", m[2].str()});
    }
  }
  return out;
}

void check_includes(std::string_view file, std::string_view text, std::string_view layer, bool host_side,
                    std::vector<Finding>& out) {
  const int rank = layer_rank(layer);
  const bool flight = is_flight_layer(layer);
  for (const Include& inc : includes_of(text)) {
    const std::string& path = inc.path;
    const std::string top = path.substr(0, path.find('/'));
    auto add = [&](const char* rule, const std::string& msg) {
      out.push_back({std::string(file), inc.line, rule, msg});
    };
    if (inc.angled && flight && !host_side && in(kBannedHeaders, path)) {
      add("heap", "<" + path + "> is not for flight code (heap, streams, host time or host randomness)");
    } else if (flight && (top == "tools" || top == "tests")) {
      add("layering", "flight code includes host code '" + path + "'");
    } else if (layer_rank(top) > rank) {
      std::string msg = "'";
      msg.append(path).append("' is in layer ").append(top).append(", above ").append(layer);
      add("layering", msg);
    } else if (rank > 0 && rank <= kTopFlightRank && top == "bsp_tile64" && !is_board_interface(path)) {
      if (path.rfind("bsp_tile64/world/", 0) == 0) {
        add("truth", "'" + path + "' is the world's truth; flight code sees only what devices report");
      } else {
        add("truth", "'" + path + "' is not a board interface header (bsp_tile64/api/); " + std::string(layer) +
                         " sees the board, its devices and the network only through those");
      }
    }
  }
}

/** "a/./b/../c" -> "a/c"; "./x" -> "x". */
std::string normal_path(const std::string& p) {
  std::string n = std::filesystem::path(p).lexically_normal().generic_string();
  return n.rfind("./", 0) == 0 ? n.substr(2) : n;
}

struct Edge {
  std::size_t to;
  int line;
};

/** Edges of the include graph: for each source, the includes that name another source. */
std::vector<std::vector<Edge>> include_graph(const std::vector<Source>& sources) {
  std::map<std::string, std::size_t> index;
  for (std::size_t i = 0; i < sources.size(); ++i) {
    index.emplace(normal_path(sources[i].path), i);
  }
  std::vector<std::vector<Edge>> graph(sources.size());
  for (std::size_t i = 0; i < sources.size(); ++i) {
    const std::string dir = std::filesystem::path(normal_path(sources[i].path)).parent_path().generic_string();
    for (const Include& inc : includes_of(sources[i].text)) {
      // As the compiler looks: a quoted name in the including file's folder first, then from the root (-I.).
      auto it = index.end();
      if (!inc.angled && !dir.empty()) {
        it = index.find(normal_path(dir + "/" + inc.path));
      }
      if (it == index.end()) {
        it = index.find(normal_path(inc.path));
      }
      if (it != index.end()) {
        graph[i].push_back({it->second, inc.line});
      }
    }
  }
  return graph;
}

}  // namespace

int layer_rank(std::string_view layer) {
  for (const Layer& l : kLayers) {
    if (l.name == layer) {
      return l.rank;
    }
  }
  return -1;
}

bool is_flight_layer(std::string_view layer) {
  const int rank = layer_rank(layer);
  return rank >= 0 && rank <= kTopFlightRank;
}

std::string layer_of(std::string_view path) {
  std::string p(path);
  if (p.rfind("./", 0) == 0) {
    p = p.substr(2);
  }
  const std::string top = p.substr(0, p.find('/'));
  return layer_rank(top) >= 0 ? top : std::string();
}

bool is_board_interface(std::string_view path) {
  if (path.rfind(kBoardInterfaceDir, 0) != 0) {
    return false;
  }
  const std::string_view name = path.substr(kBoardInterfaceDir.size());
  return !name.empty() && name.find('/') == std::string_view::npos && name.find("..") == std::string_view::npos;
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
  const bool host = host_side || !is_flight_layer(layer);
  check_includes(file, text, layer, host, out);
  if (!host) {
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
  std::vector<Finding> out;
  const std::vector<Finding> f = check_sources(read_sources(".", {path}, out));
  out.insert(out.end(), f.begin(), f.end());
  return out;
}

std::vector<Finding> find_include_cycles(const std::vector<Source>& sources) {
  // Iterative depth-first walk (white, grey on the stack, black done); an edge
  // to a grey file closes a cycle. Starting points and edges in a fixed order
  // make the findings the same on every run.
  const std::vector<std::vector<Edge>> graph = include_graph(sources);
  std::vector<std::size_t> order(sources.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    order[i] = i;
  }
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return sources[a].path < sources[b].path; });
  enum class Colour : std::uint8_t { kWhite, kGrey, kBlack };
  std::vector<Colour> colour(sources.size(), Colour::kWhite);
  struct Frame {
    std::size_t node;
    std::size_t next_edge;
  };
  std::vector<Finding> out;
  for (const std::size_t start : order) {
    if (colour[start] != Colour::kWhite) {
      continue;
    }
    std::vector<Frame> stack{{start, 0U}};
    colour[start] = Colour::kGrey;
    while (!stack.empty()) {
      const std::size_t node = stack.back().node;
      if (stack.back().next_edge == graph[node].size()) {
        colour[node] = Colour::kBlack;
        stack.pop_back();
        continue;
      }
      const Edge e = graph[node][stack.back().next_edge++];
      if (colour[e.to] == Colour::kWhite) {
        colour[e.to] = Colour::kGrey;
        stack.push_back({e.to, 0U});
      } else if (colour[e.to] == Colour::kGrey) {
        auto first = std::find_if(stack.begin(), stack.end(), [&](const Frame& f) { return f.node == e.to; });
        std::string msg = "include cycle: ";
        for (auto it = first; it != stack.end(); ++it) {
          msg.append(sources[it->node].path).append(" -> ");
        }
        msg.append(sources[e.to].path).append("; break it (a header that both need, or one direction only)");
        out.push_back({sources[node].path, e.line, "cycle", msg});
      }
    }
  }
  return out;
}

std::vector<Finding> check_sources(const std::vector<Source>& sources) {
  std::vector<Finding> out;
  for (const Source& s : sources) {
    // A host/ folder inside a layer holds host infrastructure (the board's heap guard).
    const bool host_side = s.path.find("/host/") != std::string::npos;
    const std::vector<Finding> f = check_source(s.path, s.text, layer_of(s.path), host_side);
    out.insert(out.end(), f.begin(), f.end());
  }
  const std::vector<Finding> cycles = find_include_cycles(sources);
  out.insert(out.end(), cycles.begin(), cycles.end());
  return out;
}

std::vector<std::string> project_files(const std::string& root) {
  namespace fs = std::filesystem;
  std::vector<std::string> out;
  for (const Layer& l : kLayers) {
    const fs::path dir = fs::path(root) / l.name;
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) {
      continue;
    }
    for (fs::recursive_directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
      const fs::path& p = it->path();
      const std::string ext = p.extension().string();
      if (!it->is_regular_file(ec) || (ext != ".cpp" && ext != ".hpp" && ext != ".h")) {
        continue;
      }
      std::string rel = p.lexically_relative(root).generic_string();
      if (rel.rfind(kFixtures, 0) != 0) {
        out.push_back(std::move(rel));
      }
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<Source> read_sources(const std::string& root, const std::vector<std::string>& paths,
                                 std::vector<Finding>& errors) {
  std::vector<Source> out;
  for (const std::string& rel : paths) {
    std::ifstream in(std::filesystem::path(root) / rel);
    if (!in) {
      errors.push_back({rel, 0, "io", "cannot read file"});
      continue;
    }
    std::ostringstream ss;
    ss << in.rdbuf();
    out.push_back({normal_path(rel), ss.str()});
  }
  return out;
}

}  // namespace tools::flight_rules
