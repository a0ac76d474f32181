# SPDX-License-Identifier: Apache-2.0
#
# vdb_warnings: an INTERFACE target carrying the warning flags for code of this
# project (library, tests, apps, examples, benchmarks). Link it PRIVATE, and
# from an installed target only as $<BUILD_INTERFACE:vdb_warnings>, so that it
# never reaches a downstream project. VDB_WERROR turns warnings into errors.

include_guard(GLOBAL)

add_library(vdb_warnings INTERFACE)
if(MSVC)
    target_compile_options(vdb_warnings INTERFACE /W4 /permissive- $<$<BOOL:${VDB_WERROR}>:/WX>)
else()
    target_compile_options(vdb_warnings INTERFACE -Wall -Wextra -Wpedantic
                                                  $<$<BOOL:${VDB_WERROR}>:-Werror>)
endif()
