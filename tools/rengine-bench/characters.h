// rengine-bench --characters: what a character update costs (microseconds, the world's own
// step excluded) and how exact it is, on the scenes a game has: characters walking across a
// floor of tiles (the error: the largest departure from the commanded speed and from the
// starting height, which walking across seams must not change), standing still on a turning
// deck (the error: how far each drifts from its place on it), climbing stairs (the error:
// the final height against the landing's), and pushing crates about (time only). The time
// includes what the queries' tree costs after each step of the world (its refit over every
// body, shared by every query of the frame): with one character on 2304 tiles, most of it.
#pragma once

#include <string>
#include <vector>

namespace rbench {

struct CharacterRow {
  std::string scene;
  int characters = 0;
  int updates = 0;         // per character
  double microseconds = 0; // median over the repeats, per character update
  double error = 0;        // the scene's error (below), the largest over the characters
  std::string unit;
};

// quick: fewer characters and updates (a smoke run). Medians over `repeats` timed runs.
std::vector<CharacterRow> RunCharacters(bool quick, int repeats);
void PrintCharacterTable(const std::vector<CharacterRow>& rows);
bool WriteCharacterCsv(const std::string& path, const std::vector<CharacterRow>& rows);

}  // namespace rbench
