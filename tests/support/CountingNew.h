// Heap allocations counted: a test binary that links support/CountingNew.cpp replaces the
// global operator new (plain and aligned) with counting ones, so a test can check that an
// operation allocates nothing. In its own file: a caller that saw the replacement inline
// would be warned of a mismatched new and delete.
#pragma once

#include <cstddef>

namespace REngine::test {

// Calls of operator new (any form) since the program started.
std::size_t HeapAllocations();

}  // namespace REngine::test
