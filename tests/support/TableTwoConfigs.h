// SPDX-License-Identifier: Apache-2.0
// Every configuration of the paper's Table II with float values, for typed tests: the tree type,
// whether an InternalNode stands on top, and the log2 edges of its nodes below any root, top
// first (written out here rather than read from the templates).

#pragma once

#include <vdb/tree/TreeConfigs.h>

#include <Oracles.h>

namespace vdb::test::configs {

struct HashTree543 : test::TreeConfig<tree::HashTree543<float>, false, 5, 4, 3> {
    static constexpr const char* NAME = "HashTree543";
};
struct MapTree543 : test::TreeConfig<tree::MapTree543<float>, false, 5, 4, 3> {
    static constexpr const char* NAME = "MapTree543";
};
struct HashTree432 : test::TreeConfig<tree::HashTree432<float>, false, 4, 3, 2> {
    static constexpr const char* NAME = "HashTree432";
};
struct MapTree432 : test::TreeConfig<tree::MapTree432<float>, false, 4, 3, 2> {
    static constexpr const char* NAME = "MapTree432";
};
struct FixedTree76543 : test::TreeConfig<tree::FixedTree76543<float>, true, 7, 6, 5, 4, 3> {
    static constexpr const char* NAME = "FixedTree76543";
};
struct FixedTree6543 : test::TreeConfig<tree::FixedTree6543<float>, true, 6, 5, 4, 3> {
    static constexpr const char* NAME = "FixedTree6543";
};
struct FixedTree643 : test::TreeConfig<tree::FixedTree643<float>, true, 6, 4, 3> {
    static constexpr const char* NAME = "FixedTree643";
};
struct FixedTree103 : test::TreeConfig<tree::FixedTree103<float>, true, 10, 3> {
    static constexpr const char* NAME = "FixedTree103";
};
struct FixedTree6545 : test::TreeConfig<tree::FixedTree6545<float>, true, 6, 5, 4, 5> {
    static constexpr const char* NAME = "FixedTree6545";
};
struct FixedTree6544 : test::TreeConfig<tree::FixedTree6544<float>, true, 6, 5, 4, 4> {
    static constexpr const char* NAME = "FixedTree6544";
};
struct FixedTree6542 : test::TreeConfig<tree::FixedTree6542<float>, true, 6, 5, 4, 2> {
    static constexpr const char* NAME = "FixedTree6542";
};
struct FixedTree6666 : test::TreeConfig<tree::FixedTree6666<float>, true, 6, 6, 6, 6> {
    static constexpr const char* NAME = "FixedTree6666";
};
struct FixedTree5555 : test::TreeConfig<tree::FixedTree5555<float>, true, 5, 5, 5, 5> {
    static constexpr const char* NAME = "FixedTree5555";
};
struct FixedTree4444 : test::TreeConfig<tree::FixedTree4444<float>, true, 4, 4, 4, 4> {
    static constexpr const char* NAME = "FixedTree4444";
};
struct FixedTree3333 : test::TreeConfig<tree::FixedTree3333<float>, true, 3, 3, 3, 3> {
    static constexpr const char* NAME = "FixedTree3333";
};

}  // namespace vdb::test::configs
