#include <gtest/gtest.h>

#include "renderer/decomposition/lpe_automaton.h"

namespace pathfarm {
namespace {

// The expression index that accepts `path` (a string over E, D, R, T).
int classify(const LpeAutomaton& automaton, const std::string& path) {
  int state = automaton.initial();
  for (char c : path) {
    const PathSymbol s = c == 'E' ? PathSymbol::E : c == 'D' ? PathSymbol::D : c == 'R' ? PathSymbol::R : PathSymbol::T;
    state = automaton.next(state, s);
  }
  return automaton.accepting(state);
}

TEST(LpeAutomaton, DefaultDecompositionRoutesPathsFirstListedWins) {
  // diffuse_direct, diffuse_indirect, reflection, transmission; 4 is the residual.
  const LpeAutomaton a({"ED", "ED.+", "ERD.*", "ETTD.*"});
  EXPECT_EQ(classify(a, "ED"), 0);
  EXPECT_EQ(classify(a, "EDD"), 1);
  EXPECT_EQ(classify(a, "EDRTD"), 1);
  EXPECT_EQ(classify(a, "ERD"), 2);
  EXPECT_EQ(classify(a, "ERDDR"), 2);
  EXPECT_EQ(classify(a, "ETTD"), 3);
  EXPECT_EQ(classify(a, "ETTDD"), 3);
  EXPECT_EQ(classify(a, "E"), 4);      // an emitter seen directly
  EXPECT_EQ(classify(a, "ER"), 4);     // an emitter in a mirror
  EXPECT_EQ(classify(a, "ETD"), 4);    // one refraction only
  EXPECT_EQ(classify(a, "ERRD"), 4);   // two mirrors
  EXPECT_EQ(classify(a, "ETTTTD"), 4);
}

TEST(LpeAutomaton, OverlapsGoToTheFirstListed) {
  const LpeAutomaton a({"E.*D", "ED"});
  EXPECT_EQ(classify(a, "ED"), 0);  // both accept; the first wins
  const LpeAutomaton b({"ED", "E.*D"});
  EXPECT_EQ(classify(b, "ED"), 0);
  EXPECT_EQ(classify(b, "ERD"), 1);
}

TEST(LpeAutomaton, OperatorsAndGroups) {
  const LpeAutomaton a({"E(R|T)+D", "E(DR)*D"});
  EXPECT_EQ(classify(a, "ERD"), 0);
  EXPECT_EQ(classify(a, "ETRTD"), 0);
  EXPECT_EQ(classify(a, "ED"), 1);
  EXPECT_EQ(classify(a, "EDRD"), 1);
  EXPECT_EQ(classify(a, "EDRDRD"), 1);
  EXPECT_EQ(classify(a, "EDD"), 2);
  EXPECT_EQ(classify(a, "ED"), 1);
  const LpeAutomaton none;
  EXPECT_EQ(classify(none, "ED"), 0);  // everything is residual
}

TEST(LpeAutomaton, AliveTellsWhichExpressionsCanStillMatch) {
  const LpeAutomaton a({"ED", "ERD.*"});
  const int afterE = a.next(a.initial(), PathSymbol::E);
  EXPECT_TRUE(a.alive(afterE, 0));
  EXPECT_TRUE(a.alive(afterE, 1));
  const int afterER = a.next(afterE, PathSymbol::R);
  EXPECT_FALSE(a.alive(afterER, 0));
  EXPECT_TRUE(a.alive(afterER, 1));
  const int afterED = a.next(afterE, PathSymbol::D);
  EXPECT_TRUE(a.alive(afterED, 0));
  EXPECT_FALSE(a.alive(afterED, 1));
  const int dead = a.next(afterED, PathSymbol::D);
  EXPECT_FALSE(a.alive(dead, 0));
  EXPECT_EQ(a.accepting(dead), 2);
}

TEST(LpeAutomaton, MalformedExpressionsNameThePosition) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"", "at position 0: empty expression"},
      {"ED(R", "at position 4: expected ')' to close the '(' at position 2"},
      {"ED)", "at position 2: unbalanced ')'"},
      {"*ED", "at position 0: '*' repeats nothing"},
      {"EX", "at position 1: unknown symbol 'X'"},
      {"ED|", "at position 3: expected a symbol"},
      {"E()", "at position 2: expected a symbol"},
  };
  for (const auto& [expression, expected] : cases) {
    try {
      LpeAutomaton({"ED", expression});
      ADD_FAILURE() << "accepted \"" << expression << "\"";
    } catch (const LpeError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("\"" + expression + "\""), std::string::npos) << e.what();
    }
  }
}

// Found by bench/fuzz.sh --target shot_json: a "decompose" of "E.*D" followed by n dots
// needs an automaton of 2^n states (24 characters took 28 s). What no decomposition needs
// is refused, naming why: more than 1024 states, 4096 characters, parentheses 64 deep.
TEST(LpeAutomaton, ExpressionsTooCostlyToCompileAreRefused) {
  EXPECT_EQ(LpeAutomaton({"E.*D" + std::string(8, '.')}).stateCount(), 515);
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"E.*D" + std::string(12, '.')}, "an automaton of more than 1024 states"},
      {{"ED", "E" + std::string(4095, 'D')}, "4098 characters long; at most 4096"},
      {{"E" + std::string(65, '(') + "D" + std::string(65, ')')}, "at position 65: parentheses nested more than 64 deep"},
  };
  for (const auto& [expressions, expected] : cases) {
    try {
      LpeAutomaton{expressions};
      ADD_FAILURE() << "accepted \"" << expressions.back().substr(0, 40) << "...\"";
    } catch (const LpeError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  }
  EXPECT_NO_THROW(LpeAutomaton({"E" + std::string(64, '(') + "D" + std::string(64, ')')}));
}

}  // namespace
}  // namespace pathfarm
