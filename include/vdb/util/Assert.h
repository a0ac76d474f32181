// SPDX-License-Identifier: Apache-2.0
/// @file
/// VDB_ASSERT: a precondition check that is active in debug builds and compiled out with NDEBUG.

#pragma once

#include <cstdio>
#include <cstdlib>

namespace vdb::util::detail {

[[noreturn]] inline void assertFailed(const char* expr, const char* file, int line) {
    std::fprintf(stderr, "%s:%d: VDB_ASSERT(%s) failed\n", file, line, expr);
    std::abort();
}

}  // namespace vdb::util::detail

#ifdef NDEBUG
#define VDB_ASSERT(cond) ((void)0)
#else
#define VDB_ASSERT(cond) \
    ((cond) ? (void)0 : ::vdb::util::detail::assertFailed(#cond, __FILE__, __LINE__))
#endif
