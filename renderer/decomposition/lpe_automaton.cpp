#include "renderer/decomposition/lpe_automaton.h"

#include <algorithm>
#include <map>

namespace pathfarm {
namespace {

// Thompson's construction: every node has epsilon edges and edges on a set of symbols.
struct Nfa {
  struct Node {
    std::vector<int> epsilon;
    std::vector<std::pair<uint8_t, int>> edges;  // (symbol mask, target)
    int accepts = -1;                            // expression index, or -1
  };
  std::vector<Node> nodes;

  int add() {
    nodes.emplace_back();
    return static_cast<int>(nodes.size()) - 1;
  }
};

struct Fragment {
  int start, end;
};

constexpr uint8_t mask(PathSymbol s) { return static_cast<uint8_t>(1u << static_cast<unsigned>(s)); }
constexpr uint8_t kAnyVertex = mask(PathSymbol::D) | mask(PathSymbol::R) | mask(PathSymbol::T);

class Parser {
 public:
  Parser(const std::string& text, Nfa& nfa) : text_(text), nfa_(nfa) {}

  Fragment parse() {
    if (text_.empty()) fail(0, "empty expression");
    const Fragment f = alternation();
    if (pos_ < text_.size()) fail(pos_, text_[pos_] == ')' ? "unbalanced ')'" : "unexpected '" + std::string(1, text_[pos_]) + "'");
    return f;
  }

 private:
  [[noreturn]] void fail(size_t at, const std::string& what) const {
    throw LpeError("light-path expression \"" + text_ + "\" at position " + std::to_string(at) + ": " + what);
  }

  Fragment alternation() {
    Fragment f = concatenation();
    while (pos_ < text_.size() && text_[pos_] == '|') {
      ++pos_;
      const Fragment g = concatenation();
      const int start = nfa_.add(), end = nfa_.add();
      nfa_.nodes[static_cast<size_t>(start)].epsilon = {f.start, g.start};
      nfa_.nodes[static_cast<size_t>(f.end)].epsilon.push_back(end);
      nfa_.nodes[static_cast<size_t>(g.end)].epsilon.push_back(end);
      f = {start, end};
    }
    return f;
  }

  Fragment concatenation() {
    if (pos_ >= text_.size() || text_[pos_] == '|' || text_[pos_] == ')')
      fail(pos_, "expected a symbol (E, D, R, T, .) or '('");
    Fragment f = repetition();
    while (pos_ < text_.size() && text_[pos_] != '|' && text_[pos_] != ')') {
      const Fragment g = repetition();
      nfa_.nodes[static_cast<size_t>(f.end)].epsilon.push_back(g.start);
      f.end = g.end;
    }
    return f;
  }

  Fragment repetition() {
    Fragment f = atom();
    while (pos_ < text_.size() && (text_[pos_] == '*' || text_[pos_] == '+')) {
      const bool zeroAllowed = text_[pos_] == '*';
      ++pos_;
      const int start = nfa_.add(), end = nfa_.add();
      nfa_.nodes[static_cast<size_t>(start)].epsilon.push_back(f.start);
      if (zeroAllowed) nfa_.nodes[static_cast<size_t>(start)].epsilon.push_back(end);
      nfa_.nodes[static_cast<size_t>(f.end)].epsilon = {f.start, end};
      f = {start, end};
    }
    return f;
  }

  Fragment atom() {
    const size_t at = pos_;
    const char c = text_[pos_++];
    if (c == '(') {
      // The parser recurses per '(': a deep nest would overflow the stack.
      if (++depth_ > kMaxNesting) fail(at, "parentheses nested more than " + std::to_string(kMaxNesting) + " deep");
      const Fragment f = alternation();
      --depth_;
      if (pos_ >= text_.size() || text_[pos_] != ')') fail(pos_, "expected ')' to close the '(' at position " + std::to_string(at));
      ++pos_;
      return f;
    }
    uint8_t symbols = 0;
    switch (c) {
      case 'E': symbols = mask(PathSymbol::E); break;
      case 'D': symbols = mask(PathSymbol::D); break;
      case 'R': symbols = mask(PathSymbol::R); break;
      case 'T': symbols = mask(PathSymbol::T); break;
      case '.': symbols = kAnyVertex; break;
      case '*':
      case '+': fail(at, std::string("'") + c + "' repeats nothing");
      default: fail(at, std::string("unknown symbol '") + c + "' (expected E, D, R, T, ., |, *, +, parentheses)");
    }
    const int start = nfa_.add(), end = nfa_.add();
    nfa_.nodes[static_cast<size_t>(start)].edges.push_back({symbols, end});
    return {start, end};
  }

  static constexpr int kMaxNesting = 64;
  const std::string& text_;
  Nfa& nfa_;
  size_t pos_ = 0;
  int depth_ = 0;
};

std::vector<int> closure(const Nfa& nfa, std::vector<int> set) {
  std::vector<bool> seen(nfa.nodes.size(), false);
  for (int n : set) seen[static_cast<size_t>(n)] = true;
  for (size_t i = 0; i < set.size(); ++i) {
    for (int m : nfa.nodes[static_cast<size_t>(set[i])].epsilon) {
      if (!seen[static_cast<size_t>(m)]) {
        seen[static_cast<size_t>(m)] = true;
        set.push_back(m);
      }
    }
  }
  std::sort(set.begin(), set.end());
  return set;
}

// For each node, a bit per expression it can still reach the accepting node of: the
// accepting nodes' bits spread backwards along every edge, a node again only when its
// bits grew (at most 64 times each).
std::vector<uint64_t> coReachable(const Nfa& nfa) {
  std::vector<std::vector<int>> predecessors(nfa.nodes.size());
  for (size_t n = 0; n < nfa.nodes.size(); ++n) {
    for (int m : nfa.nodes[n].epsilon) predecessors[static_cast<size_t>(m)].push_back(static_cast<int>(n));
    for (const auto& [symbols, m] : nfa.nodes[n].edges) predecessors[static_cast<size_t>(m)].push_back(static_cast<int>(n));
  }
  std::vector<uint64_t> reach(nfa.nodes.size(), 0);
  std::vector<int> grown;
  for (size_t n = 0; n < nfa.nodes.size(); ++n) {
    if (nfa.nodes[n].accepts < 0) continue;
    reach[n] = uint64_t{1} << nfa.nodes[n].accepts;
    grown.push_back(static_cast<int>(n));
  }
  while (!grown.empty()) {
    const uint64_t bits = reach[static_cast<size_t>(grown.back())];
    const auto& from = predecessors[static_cast<size_t>(grown.back())];
    grown.pop_back();
    for (int p : from) {
      if ((reach[static_cast<size_t>(p)] | bits) == reach[static_cast<size_t>(p)]) continue;
      reach[static_cast<size_t>(p)] |= bits;
      grown.push_back(p);
    }
  }
  return reach;
}

// Bounds on what the construction below is given, so that no decomposition takes more
// than milliseconds to compile: an automaton's states (a subset construction can need 2^n
// of them: "E.*D" followed by n dots remembers which of the last n vertices were diffuse;
// 24 characters of it took 28 s, found by bench/fuzz.sh --target shot_json; real
// decompositions need tens), and the expressions' length, which sizes every state's set.
constexpr size_t kMaxStates = 1024;
constexpr size_t kMaxLength = 4096;

}  // namespace

LpeAutomaton::LpeAutomaton(const std::vector<std::string>& expressions)
    : expressionCount_(static_cast<int>(expressions.size())) {
  if (expressions.size() > 63) throw LpeError("at most 63 light-path expressions can be combined");
  size_t length = 0;
  for (const std::string& expression : expressions) length += expression.size();
  if (length > kMaxLength)
    throw LpeError("the light-path expressions are " + std::to_string(length) + " characters long; at most " +
                   std::to_string(kMaxLength));
  Nfa nfa;
  const int root = nfa.add();
  for (size_t k = 0; k < expressions.size(); ++k) {
    const Fragment f = Parser(expressions[k], nfa).parse();
    nfa.nodes[static_cast<size_t>(root)].epsilon.push_back(f.start);
    nfa.nodes[static_cast<size_t>(f.end)].accepts = static_cast<int>(k);
  }
  const std::vector<uint64_t> reach = coReachable(nfa);

  // Subset construction; the empty set is the dead state, where only the residual is left.
  std::map<std::vector<int>, int> index;
  std::vector<std::vector<int>> sets;
  const auto stateOf = [&](std::vector<int> set) {
    const auto [it, inserted] = index.emplace(set, static_cast<int>(sets.size()));
    if (inserted) sets.push_back(std::move(set));
    return it->second;
  };
  stateOf(closure(nfa, {root}));
  for (size_t s = 0; s < sets.size(); ++s) {
    if (sets.size() > kMaxStates)
      throw LpeError("the light-path expressions need an automaton of more than " + std::to_string(kMaxStates) +
                     " states; use fewer '.' after a '*'");
    for (int symbol = 0; symbol < kPathSymbols; ++symbol) {
      std::vector<int> target;
      for (int n : sets[s]) {
        for (const auto& [symbols, m] : nfa.nodes[static_cast<size_t>(n)].edges)
          if (symbols & (1u << symbol)) target.push_back(m);
      }
      const int t = stateOf(closure(nfa, target));
      transitions_.push_back(t);
    }
  }
  for (const auto& set : sets) {
    int accepts = expressionCount_;
    uint64_t alive = 0;
    for (int n : set) {
      const int a = nfa.nodes[static_cast<size_t>(n)].accepts;
      if (a >= 0) accepts = std::min(accepts, a);
      alive |= reach[static_cast<size_t>(n)];
    }
    accepting_.push_back(accepts);
    alive_.push_back(alive);
  }
}

}  // namespace pathfarm
