// The character in a moving world (RCharacter.h): placeholder filled below.
#include <gtest/gtest.h>

#include "character/CharacterWorld.h"
