// Private to REnginePhysics: the characters' record of a world state (RWorldState.h), after
// the container: their count, then each one's name and RCharacter::RState.
#pragma once

#include <REnginePhysics/RCharacter.h>

#include "state/RStateFormat.h"

#include <vector>

namespace REngine::state {

// Writes the count (0 for none) and each character's state.
void WriteCharacters(RWriter& w, const std::vector<RCharacter>* characters);
// Reads the record and returns copies of `target` with the saved states restored (nothing of
// `target` changes): the state's characters must be target's, by count and name, and every
// value one RCharacter::Restore accepts. A state with characters needs a target.
std::vector<RCharacter> ReadCharacters(RReader& r, const std::vector<RCharacter>* target);

}  // namespace REngine::state
