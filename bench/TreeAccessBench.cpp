// SPDX-License-Identifier: Apache-2.0
// The tree access benchmarks of the paper's Table II (Museth 2013, section 5): this library
// against OpenVDB 10 on the same Enright sphere band, in one process.
//
// Every benchmark is a template on a library tag: Vdb (the standard [Hash,5,4,3] tree),
// VdbIndexed (the same with its leaf index built; lookups and memory only), VdbFixed6543
// ([6,5,4,3], a fixed internal node on top), VdbMap543 ([Map,5,4,3]) and OpenVdb
// (openvdb::FloatTree, whose root table is a std::map: [Map,5,4,3]), plus OpenVdbTwin, a
// second OpenVDB tree whose ratio to the first is the noise floor. Each library builds its
// tree from the same coordinate list in the same shuffled order. After the Google Benchmark
// run, main() prints the median and the minimum time per operation of each library over the
// repetitions, and its ratio to OpenVDB.
//
//   BM_MemUsage        tree.memUsage() and the RSS growth while the tree is built
//   BM_CachedLookup    accessor lookups, Args {coordinates, run length}: {100, 100000} is
//                      Table II (each coordinate repeated 10^5 times in a row, 10^7 lookups);
//                      {100, 1} visits the 100 coordinates round-robin, so that each lookup
//                      leaves the accessor's cached leaf
//   BM_TopDownLookup   the same with tree.getValue(), a root-to-leaf walk every time
//   BM_CachedRandomLookup / BM_TopDownRandomLookup
//                      10^7 lookups of distinct random active voxels (memory bound)
//   BM_ValueIteration  sum of all active values through tree.cbeginValueOn()
//   BM_LeafIteration   the same through tree.cbeginLeaf() and each leaf's value mask
//   BM_ArraySum, BM_LeafBytesSum, BM_LeafBytesStream ("Floor")
//                      the floors of the two: the active values summed from one array; every
//                      leaf value (the bytes the iterations stream) summed the same way; the
//                      same bytes read at memory speed
//   BM_LookupFloor, BM_RandomLookupFloor ("Floor")
//                      the floors of the lookups: the same loops with the tree replaced by one
//                      array read (the leaf offset of the coordinates in one leaf's values; the
//                      value of each random voxel in one array of every leaf value)
//   BM_RandomInsert / BM_RandomInsertTopDown
//                      the whole band in random order into an empty tree, with an accessor
//                      or with tree.setValue()
//
// With --markdown FILE (taken out of the arguments before Google Benchmark reads them) the
// program also writes the tables of docs/BENCHMARKS.md to FILE and one overview line to
// FILE.status (scripts/bench).

#include <vdb/tree/TreeConfigs.h>
#include <vdb/tree/ValueAccessor.h>
#include <vdb/vdb.h>

#include "BenchCommon.h"
#include <benchmark/benchmark.h>
#include <openvdb/openvdb.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

namespace {

using vdb::bench::BandVoxel;
using vdb::bench::EnrightSphere;

// ---- Fixed sizes and seeds ----

constexpr int kResolution = 1024;
constexpr int64_t kLookups = 10'000'000;  // lookups per benchmark iteration
constexpr int kProbeCount = 100;          // Table II: 100 random coordinates
constexpr int64_t kTableTwoRunLength = kLookups / kProbeCount;
constexpr float kBackground = float(EnrightSphere::kHalfWidth);  // values are in voxel units
constexpr uint64_t kInsertSeed = 20130601;                       // insertion order
constexpr uint64_t kProbeSeed = 7;                               // the 100 Table II coordinates
constexpr uint64_t kRandomProbeSeed = 11;                        // the 10^7 distinct lookups

// ---- Library tags ----

struct Vdb {
    static constexpr const char* kName = "Vdb";
    static constexpr const char* kConfig = "[Hash,5,4,3]";
    using TreeType = vdb::FloatTree;
    using CoordType = vdb::Coord;
    template <typename TreeT>
    using Accessor = vdb::tree::ValueAccessor<TreeT>;
};

// The standard tree with its leaf index built (Tree::buildLeafIndex()): top-down reads and
// accessor misses reach a leaf in one hash probe. Only the lookups and the memory differ from
// Vdb, so only those run.
struct VdbIndexed : Vdb {
    static constexpr const char* kName = "VdbIndexed";
    static constexpr const char* kConfig = "[Hash,5,4,3] + leaf index";
    static constexpr bool kLeafIndex = true;
};

template <typename Lib>
constexpr bool kIndexed = requires {
    Lib::kLeafIndex;
};

struct VdbFixed6543 {
    static constexpr const char* kName = "VdbFixed6543";
    static constexpr const char* kConfig = "[6,5,4,3]";
    using TreeType = vdb::tree::FixedTree6543<float>;
    using CoordType = vdb::Coord;
    template <typename TreeT>
    using Accessor = vdb::tree::ValueAccessor<TreeT>;
};

struct VdbMap543 {
    static constexpr const char* kName = "VdbMap543";
    static constexpr const char* kConfig = "[Map,5,4,3]";
    using TreeType = vdb::tree::MapTree543<float>;
    using CoordType = vdb::Coord;
    template <typename TreeT>
    using Accessor = vdb::tree::ValueAccessor<TreeT>;
};

// OpenVDB's RootNode keeps its table in a std::map: [Map,5,4,3] in the paper's notation.
// The name under which the library-independent floor is registered.
struct Floor {
    static constexpr const char* kName = "Floor";
};

struct OpenVdb {
    static constexpr const char* kName = "OpenVdb";
    static constexpr const char* kConfig = "[Map,5,4,3]";
    using TreeType = openvdb::FloatTree;
    using CoordType = openvdb::Coord;
    template <typename TreeT>
    using Accessor = openvdb::tree::ValueAccessor<TreeT>;
};

// A second OpenVDB tree built the same way: its ratio to OpenVdb is the noise floor of the
// comparison (run-to-run noise plus the effect of where the heap placed each tree's nodes).
struct OpenVdbTwin : OpenVdb {
    static constexpr const char* kName = "OpenVdbTwin";
};

// ---- Shared inputs ----

struct Inputs {
    std::vector<BandVoxel> band;          // every band voxel, in the shuffled insertion order
    std::vector<BandVoxel> probes;        // kProbeCount random band voxels
    std::vector<BandVoxel> randomProbes;  // kLookups random band voxels
};

const Inputs& inputs() {
    static const Inputs in = [] {
        Inputs made;
        made.band = vdb::bench::makeEnrightBand(kResolution);
        vdb::bench::shuffle(made.band, kInsertSeed);
        made.probes = vdb::bench::sample(made.band, kProbeCount, kProbeSeed);
        made.randomProbes = vdb::bench::sample(made.band, size_t(kLookups), kRandomProbeSeed);
        return made;
    }();
    return in;
}

template <typename Lib>
typename Lib::CoordType coordOf(const BandVoxel& v) {
    return typename Lib::CoordType(v.x, v.y, v.z);
}

template <typename Lib>
std::unique_ptr<typename Lib::TreeType> buildWithAccessor(const std::vector<BandVoxel>& band) {
    using TreeT = typename Lib::TreeType;
    auto tree = std::make_unique<TreeT>(kBackground);
    typename Lib::template Accessor<TreeT> acc(*tree);
    for (const BandVoxel& v : band)
        acc.setValue(coordOf<Lib>(v), v.value);
    if constexpr (kIndexed<Lib>)
        tree->buildLeafIndex();
    return tree;
}

/// The tree of library `Lib` that the lookup and iteration benchmarks read, built on first
/// use from the shuffled band and checked against it once.
template <typename Lib>
struct SharedTree {
    std::unique_ptr<typename Lib::TreeType> tree;
    std::string error;  // empty when every band voxel reads back active with its value
};

// Set once sharedTree<Lib>() has built its tree, so that the summary reports only those.
template <typename Lib>
bool sharedTreeBuilt = false;

template <typename Lib>
const SharedTree<Lib>& sharedTree() {
    static const SharedTree<Lib> shared = [] {
        sharedTreeBuilt<Lib> = true;
        SharedTree<Lib> made;
        const auto& band = inputs().band;
        made.tree = buildWithAccessor<Lib>(band);
        const uint64_t count = made.tree->activeVoxelCount();
        if (count != band.size()) {
            made.error = std::string(Lib::kName) + ": activeVoxelCount() " + std::to_string(count) +
                         " != band size " + std::to_string(band.size());
            return made;
        }
        typename Lib::template Accessor<const typename Lib::TreeType> acc(*made.tree);
        for (const BandVoxel& v : band) {
            const auto ijk = coordOf<Lib>(v);
            if (!acc.isValueOn(ijk) || acc.getValue(ijk) != v.value) {
                made.error = std::string(Lib::kName) + ": wrong value read back at (" +
                             std::to_string(v.x) + ", " + std::to_string(v.y) + ", " +
                             std::to_string(v.z) + ")";
                return made;
            }
        }
        return made;
    }();
    return shared;
}

// Keeps `value` alive in a register without a memory clobber, so that the compiler must
// compute it but may still keep the accessor's cache in registers.
inline void consume(float value) {
    asm volatile("" : : "x"(value));
}

// Records the operations per iteration: "ops" for the summary table, and "time/op" (seconds,
// shown with an SI prefix) for the console.
void setOps(benchmark::State& state, int64_t opsPerIteration) {
    state.counters["ops"] = double(opsPerIteration);
    state.counters["time/op"] =
        benchmark::Counter(double(opsPerIteration), benchmark::Counter::kIsIterationInvariantRate |
                                                        benchmark::Counter::kInvert);
}

// ---- Benchmarks ----

template <typename Lib>
void BM_MemUsage(benchmark::State& state) {
    const auto& band = inputs().band;
    double memUsage = 0, rss = 0;
    for (auto _ : state) {
        vdb::bench::releaseFreeMemory();
        const uint64_t before = vdb::bench::residentBytes();
        auto tree = buildWithAccessor<Lib>(band);
        rss = double(vdb::bench::residentBytes() - before);
        memUsage = double(tree->memUsage());
        state.PauseTiming();
        tree.reset();
        state.ResumeTiming();
    }
    state.counters["memUsage_MB"] = memUsage / (1024.0 * 1024.0);
    state.counters["rss_MB"] = rss / (1024.0 * 1024.0);
    state.counters["B/voxel"] = memUsage / double(band.size());
}

// Args {coordinates, run length}: each coordinate is looked up `run length` times in a row,
// and the list is swept until kLookups lookups are done. The coordinates are read through a
// volatile pointer, so no lookup can be hoisted out of the loop.
template <typename Lib, bool Cached>
void lookupRepeated(benchmark::State& state) {
    const auto& shared = sharedTree<Lib>();
    if (!shared.error.empty()) {
        state.SkipWithError(shared.error.c_str());
        return;
    }
    const auto& tree = *shared.tree;
    const int count = int(state.range(0));
    const int64_t runLength = state.range(1);
    const int64_t sweeps = kLookups / (count * runLength);
    const volatile BandVoxel* probes = inputs().probes.data();
    typename Lib::template Accessor<const typename Lib::TreeType> acc(tree);
    for (auto _ : state) {
        for (int64_t sweep = 0; sweep < sweeps; ++sweep) {
            for (int i = 0; i < count; ++i) {
                for (int64_t n = 0; n < runLength; ++n) {
                    const typename Lib::CoordType ijk(probes[i].x, probes[i].y, probes[i].z);
                    if constexpr (Cached) {
                        consume(acc.getValue(ijk));
                    } else {
                        consume(tree.getValue(ijk));
                    }
                }
            }
        }
    }
    setOps(state, sweeps * count * runLength);
}

template <typename Lib>
void BM_CachedLookup(benchmark::State& state) {
    lookupRepeated<Lib, true>(state);
}

template <typename Lib>
void BM_TopDownLookup(benchmark::State& state) {
    lookupRepeated<Lib, false>(state);
}

// Arg: number of lookups, each of a distinct random band voxel from a pre-generated list.
template <typename Lib, bool Cached>
void lookupRandom(benchmark::State& state) {
    const auto& shared = sharedTree<Lib>();
    if (!shared.error.empty()) {
        state.SkipWithError(shared.error.c_str());
        return;
    }
    const auto& tree = *shared.tree;
    const auto& probes = inputs().randomProbes;
    const size_t count = std::min(size_t(state.range(0)), probes.size());
    typename Lib::template Accessor<const typename Lib::TreeType> acc(tree);
    for (auto _ : state) {
        for (size_t i = 0; i < count; ++i) {
            const auto ijk = coordOf<Lib>(probes[i]);
            if constexpr (Cached) {
                consume(acc.getValue(ijk));
            } else {
                consume(tree.getValue(ijk));
            }
        }
    }
    setOps(state, int64_t(count));
}

template <typename Lib>
void BM_CachedRandomLookup(benchmark::State& state) {
    lookupRandom<Lib, true>(state);
}

template <typename Lib>
void BM_TopDownRandomLookup(benchmark::State& state) {
    lookupRandom<Lib, false>(state);
}

// The floor of the Table II lookups: the loop of lookupRepeated() with the coordinates read the
// same way, and the tree replaced by one read of a leaf's worth of values at the coordinates'
// leaf offset. What is left of a lookup's time above it is the tree's.
void BM_LookupFloor(benchmark::State& state) {
    static const std::vector<float> leaf = [] {
        std::vector<float> out(vdb::FloatTree::LeafNodeType::NUM_VALUES);
        for (size_t i = 0; i < out.size(); ++i)
            out[i] = float(i);
        return out;
    }();
    const int count = int(state.range(0));
    const int64_t runLength = state.range(1);
    const int64_t sweeps = kLookups / (count * runLength);
    const volatile BandVoxel* probes = inputs().probes.data();
    const float* values = leaf.data();
    for (auto _ : state) {
        for (int64_t sweep = 0; sweep < sweeps; ++sweep) {
            for (int i = 0; i < count; ++i) {
                for (int64_t n = 0; n < runLength; ++n) {
                    const vdb::Coord ijk(probes[i].x, probes[i].y, probes[i].z);
                    consume(values[vdb::FloatTree::LeafNodeType::coordToOffset(ijk)]);
                }
            }
        }
    }
    setOps(state, sweeps * count * runLength);
}

// Every value the tree's leaves hold, active or not, in one array in leaf order: the bytes the
// two iterations stream through (a narrow band touches nearly every cache line of its leaves).
const std::vector<float>& leafBytes();

// The floor of the random lookups: each voxel's value read from leafBytes() at its index,
// computed beforehand, so one read from memory per lookup where a tree needs a chain of them.
void BM_RandomLookupFloor(benchmark::State& state) {
    static const std::vector<uint32_t> indices = [] {
        const auto& tree = *sharedTree<Vdb>().tree;
        std::map<vdb::Coord, uint32_t> first;  // leaf origin -> index of its first value
        uint32_t next = 0;
        for (auto leaf = tree.cbeginLeaf(); leaf;
             ++leaf, next += vdb::FloatTree::LeafNodeType::NUM_VALUES)
            first.emplace(leaf->origin(), next);
        const auto& probes = inputs().randomProbes;
        std::vector<uint32_t> out(probes.size());
        for (size_t i = 0; i < probes.size(); ++i) {
            const vdb::Coord ijk = coordOf<Vdb>(probes[i]);
            out[i] = first.at(ijk.alignedDown(vdb::FloatTree::LeafNodeType::LOG2DIM)) +
                     vdb::FloatTree::LeafNodeType::coordToOffset(ijk);
        }
        return out;
    }();
    const auto& values = leafBytes();
    const size_t count = std::min(size_t(state.range(0)), indices.size());
    for (auto _ : state) {
        for (size_t i = 0; i < count; ++i)
            consume(values[indices[i]]);
    }
    setOps(state, int64_t(count));
}

template <typename Lib>
void BM_ValueIteration(benchmark::State& state) {
    const auto& shared = sharedTree<Lib>();
    if (!shared.error.empty()) {
        state.SkipWithError(shared.error.c_str());
        return;
    }
    const auto& tree = *shared.tree;
    uint64_t visited = 0;
    for (auto _ : state) {
        double sum = 0;
        visited = 0;
        for (auto it = tree.cbeginValueOn(); it; ++it) {
            sum += *it;
            ++visited;
        }
        benchmark::DoNotOptimize(sum);
    }
    if (visited != inputs().band.size())
        state.SkipWithError("value iterator missed voxels");
    setOps(state, int64_t(visited));
}

template <typename Lib>
void BM_LeafIteration(benchmark::State& state) {
    const auto& shared = sharedTree<Lib>();
    if (!shared.error.empty()) {
        state.SkipWithError(shared.error.c_str());
        return;
    }
    const auto& tree = *shared.tree;
    uint64_t visited = 0;
    for (auto _ : state) {
        double sum = 0;
        visited = 0;
        for (auto leaf = tree.cbeginLeaf(); leaf; ++leaf) {
            for (auto bit = leaf->getValueMask().beginOn(); bit; ++bit) {
                sum += leaf->getValue(bit.pos());
                ++visited;
            }
        }
        benchmark::DoNotOptimize(sum);
    }
    if (visited != inputs().band.size())
        state.SkipWithError("leaf iteration missed voxels");
    setOps(state, int64_t(visited));
}

// The floor of the two iterations: the same active values, already gathered into one array
// in the tree's iteration order, summed the same way. Registered once, as library "Floor".
void BM_ArraySum(benchmark::State& state) {
    static const std::vector<float> values = [] {
        const auto& shared = sharedTree<Vdb>();
        std::vector<float> out;
        out.reserve(inputs().band.size());
        for (auto it = shared.tree->cbeginValueOn(); it; ++it)
            out.push_back(*it);
        return out;
    }();
    for (auto _ : state) {
        double sum = 0;
        for (const float v : values)
            sum += v;
        benchmark::DoNotOptimize(sum);
    }
    setOps(state, int64_t(values.size()));
}

const std::vector<float>& leafBytes() {
    static const std::vector<float> values = [] {
        const auto& shared = sharedTree<Vdb>();
        std::vector<float> out;
        for (auto leaf = shared.tree->cbeginLeaf(); leaf; ++leaf) {
            const auto buffer = leaf->buffer(0);
            out.insert(out.end(), buffer.begin(), buffer.end());
        }
        return out;
    }();
    return values;
}

// Two more floors, per active voxel like the others: the leaves' value bytes summed the same way
// as the iterations (into a double, in order), and streamed at memory speed (sixteen
// independent float sums the compiler vectorizes: the machine's read bandwidth on these bytes).
void BM_LeafBytesSum(benchmark::State& state) {
    const auto& values = leafBytes();
    for (auto _ : state) {
        double sum = 0;
        for (const float v : values)
            sum += v;
        benchmark::DoNotOptimize(sum);
    }
    setOps(state, int64_t(inputs().band.size()));
}

void BM_LeafBytesStream(benchmark::State& state) {
    const auto& values = leafBytes();
    constexpr size_t kLanes = 16;
    for (auto _ : state) {
        float lanes[kLanes] = {};
        const size_t whole = values.size() / kLanes * kLanes;
        for (size_t i = 0; i < whole; i += kLanes)
            for (size_t k = 0; k < kLanes; ++k)
                lanes[k] += values[i + k];
        double sum = 0;
        for (const float lane : lanes)
            sum += lane;
        benchmark::DoNotOptimize(sum);
    }
    setOps(state, int64_t(inputs().band.size()));
    state.counters["bytes"] = double(values.size() * sizeof(float));
}

// Tree::buildLeafIndex() over the shared tree, per leaf (counted as "voxels" in the summary's
// other-operations table, whose unit is per item).
template <typename Lib>
void BM_LeafIndexBuild(benchmark::State& state) {
    const auto& shared = sharedTree<Lib>();
    if (!shared.error.empty()) {
        state.SkipWithError(shared.error.c_str());
        return;
    }
    auto& tree = *shared.tree;
    for (auto _ : state)
        tree.buildLeafIndex();
    setOps(state, int64_t(tree.leafCount()));
}

template <typename Lib, bool Cached>
void insertRandom(benchmark::State& state) {
    using TreeT = typename Lib::TreeType;
    const auto& band = inputs().band;
    uint64_t count = 0;
    for (auto _ : state) {
        auto tree = std::make_unique<TreeT>(kBackground);
        if constexpr (Cached) {
            typename Lib::template Accessor<TreeT> acc(*tree);
            for (const BandVoxel& v : band)
                acc.setValue(coordOf<Lib>(v), v.value);
        } else {
            for (const BandVoxel& v : band)
                tree->setValue(coordOf<Lib>(v), v.value);
        }
        state.PauseTiming();
        count = tree->activeVoxelCount();
        tree.reset();
        state.ResumeTiming();
    }
    if (count != band.size())
        state.SkipWithError("insertion lost voxels");
    setOps(state, int64_t(band.size()));
}

template <typename Lib>
void BM_RandomInsert(benchmark::State& state) {
    insertRandom<Lib, true>(state);
}

template <typename Lib>
void BM_RandomInsertTopDown(benchmark::State& state) {
    insertRandom<Lib, false>(state);
}

// ---- Registration ----

// Calls `fn(std::type_identity<Lib>{})` for every library, OpenVDB first.
template <typename Fn>
void forEachLibrary(Fn&& fn) {
    fn(std::type_identity<OpenVdb>{});
    fn(std::type_identity<OpenVdbTwin>{});
    fn(std::type_identity<Vdb>{});
    fn(std::type_identity<VdbIndexed>{});
    fn(std::type_identity<VdbFixed6543>{});
    fn(std::type_identity<VdbMap543>{});
}

// Operation names in registration order; the summary lists its rows in this order.
std::vector<std::string>& operationOrder() {
    static std::vector<std::string> order;
    return order;
}

template <typename Lib>
benchmark::internal::Benchmark* add(const char* op, void (*fn)(benchmark::State&)) {
    auto& order = operationOrder();
    if (std::find(order.begin(), order.end(), op) == order.end())
        order.push_back(op);
    const std::string name = std::string(op) + "<" + Lib::kName + ">";
    return benchmark::RegisterBenchmark(name.c_str(), fn)
        ->Unit(benchmark::kMillisecond)
        ->ComputeStatistics("min", [](const std::vector<double>& v) {
            return *std::min_element(v.begin(), v.end());
        });
}

// Registers each benchmark for all libraries in turn, so that the libraries' runs of one
// operation are adjacent in the output.
void registerBenchmarks() {
    forEachLibrary([](auto lib) {
        using Lib = typename decltype(lib)::type;
        add<Lib>("BM_MemUsage", BM_MemUsage<Lib>)->Iterations(1)->Repetitions(1);
    });
    forEachLibrary([](auto lib) {
        using Lib = typename decltype(lib)::type;
        add<Lib>("BM_CachedLookup", BM_CachedLookup<Lib>)
            ->Args({kProbeCount, kTableTwoRunLength})
            ->Args({kProbeCount, 1})
            ->MinTime(0.2);
    });
    forEachLibrary([](auto lib) {
        using Lib = typename decltype(lib)::type;
        add<Lib>("BM_TopDownLookup", BM_TopDownLookup<Lib>)
            ->Args({kProbeCount, kTableTwoRunLength})
            ->Args({kProbeCount, 1})
            ->MinTime(0.2);
    });
    forEachLibrary([](auto lib) {
        using Lib = typename decltype(lib)::type;
        add<Lib>("BM_CachedRandomLookup", BM_CachedRandomLookup<Lib>)->Arg(kLookups)->Iterations(1);
    });
    forEachLibrary([](auto lib) {
        using Lib = typename decltype(lib)::type;
        add<Lib>("BM_TopDownRandomLookup", BM_TopDownRandomLookup<Lib>)
            ->Arg(kLookups)
            ->Iterations(1);
    });
    add<Floor>("BM_LookupFloor", BM_LookupFloor)
        ->Args({kProbeCount, kTableTwoRunLength})
        ->Args({kProbeCount, 1})
        ->MinTime(0.2);
    add<Floor>("BM_RandomLookupFloor", BM_RandomLookupFloor)->Arg(kLookups)->Iterations(1);
    forEachLibrary([](auto lib) {
        using Lib = typename decltype(lib)::type;
        if constexpr (!kIndexed<Lib>)
            add<Lib>("BM_ValueIteration", BM_ValueIteration<Lib>)->MinTime(0.2);
    });
    forEachLibrary([](auto lib) {
        using Lib = typename decltype(lib)::type;
        if constexpr (!kIndexed<Lib>)
            add<Lib>("BM_LeafIteration", BM_LeafIteration<Lib>)->MinTime(0.2);
    });
    add<Floor>("BM_ArraySum", BM_ArraySum)->MinTime(0.2);
    add<Floor>("BM_LeafBytesSum", BM_LeafBytesSum)->MinTime(0.2);
    add<Floor>("BM_LeafBytesStream", BM_LeafBytesStream)->MinTime(0.2);
    forEachLibrary([](auto lib) {
        using Lib = typename decltype(lib)::type;
        if constexpr (!kIndexed<Lib>)
            add<Lib>("BM_RandomInsert", BM_RandomInsert<Lib>)->Iterations(1);
    });
    forEachLibrary([](auto lib) {
        using Lib = typename decltype(lib)::type;
        if constexpr (!kIndexed<Lib>)
            add<Lib>("BM_RandomInsertTopDown", BM_RandomInsertTopDown<Lib>)->Iterations(1);
    });
    add<VdbIndexed>("BM_LeafIndexBuild", BM_LeafIndexBuild<VdbIndexed>)->MinTime(0.2);
}

// ---- Summary ----

// One benchmark result kept for the summary, per iteration.
struct Result {
    double realNs = 0;
    double cpuNs = 0;
    benchmark::UserCounters counters;
};

// Displays like the console reporter and keeps, per statistic ("median", "min", or "run" for
// a single repetition), "operation/args" and library, the result that the summary uses.
class SummaryReporter : public benchmark::ConsoleReporter {
public:
    void ReportRuns(const std::vector<Run>& runs) override {
        ConsoleReporter::ReportRuns(runs);
        for (const Run& run : runs) {
            if (run.error_occurred)
                continue;
            const bool single = run.run_type == Run::RT_Iteration && run.repetitions <= 1;
            const bool kept = run.run_type == Run::RT_Aggregate &&
                              (run.aggregate_name == "median" || run.aggregate_name == "min");
            if (!single && !kept)
                continue;
            // Names look like "BM_CachedLookup<Vdb>" with args "100/1".
            const std::string& fn = run.run_name.function_name;
            const size_t open = fn.find('<');
            if (open == std::string::npos || fn.back() != '>')
                continue;
            const std::string op =
                fn.substr(0, open) + (run.run_name.args.empty() ? "" : "/" + run.run_name.args);
            const std::string lib = fn.substr(open + 1, fn.size() - open - 2);
            const double toNs = 1e9 / benchmark::GetTimeUnitMultiplier(run.time_unit);
            Result& slot = mResults[single ? "run" : run.aggregate_name][op][lib];
            slot.realNs = run.GetAdjustedRealTime() * toNs;
            slot.cpuNs = run.GetAdjustedCPUTime() * toNs;
            slot.counters = run.counters;
            mRepetitions = std::max(mRepetitions, single ? int64_t(1) : int64_t(run.repetitions));
            if (std::find(mRows.begin(), mRows.end(), op) == mRows.end())
                mRows.push_back(op);
        }
    }

    /// Prints, for the medians and then the minimums over repetitions, one row per operation:
    /// OpenVDB's time, then each other library's time and its ratio to OpenVDB. Times are CPU
    /// (thread) nanoseconds per operation: on a quiet machine the same as wall-clock time, on a
    /// shared one without the time spent waiting for a CPU.
    void printSummary() const {
        // Rows in registration order (random interleaving reports them in any order).
        std::vector<std::string> rows = mRows;
        const auto& order = operationOrder();
        auto rank = [&](const std::string& op) {
            return std::find(order.begin(), order.end(), op.substr(0, op.find('/'))) -
                   order.begin();
        };
        std::sort(rows.begin(), rows.end(), [&](const std::string& a, const std::string& b) {
            return rank(a) != rank(b) ? rank(a) < rank(b) : a < b;
        });

        // Memory comes from single runs; times from the medians and the minimums.
        const auto run = mResults.find("run");
        for (const char* stat : {"median", "min"}) {
            const auto found = mResults.find(stat);
            if (found == mResults.end())
                continue;
            std::printf(
                "\nSummary: %s over repetitions, CPU ns per operation, ratio = library / "
                "OpenVdb\n",
                stat);
            const bool first = std::string(stat) == "median";
            printTable(rows, found->second,
                       first && run != mResults.end() ? &run->second : nullptr);
        }
        if (mResults.count("median") == 0 && run != mResults.end()) {
            std::printf(
                "\nSummary: single runs, CPU ns per operation, ratio = library / OpenVdb\n");
            printTable(rows, run->second, &run->second);
        }

        const double wait = worstWait();
        if (wait > 1.05) {
            std::printf(
                "Note: wall-clock time exceeded CPU time by up to %.0f%%: other processes "
                "competed for the CPU and its caches; read the OpenVdbTwin column (the noise "
                "floor) before the others.\n",
                100.0 * (wait - 1.0));
        }
    }

    /// Adds the tables of docs/BENCHMARKS.md to `md`, Table II's lookups and the other
    /// operations, and the overview line. Times are CPU nanoseconds per operation, the medians
    /// over the repetitions as in the printed summary (single runs where there was one
    /// repetition); each library's figure is followed by its ratio to OpenVdb's.
    void addMarkdown(vdb::bench::MarkdownReport& md) const {
        std::vector<std::string> libs, headers;
        forEachLibrary([&](auto lib) {
            using Lib = typename decltype(lib)::type;
            libs.push_back(Lib::kName);
            // OpenVdbTwin is OpenVdb's configuration again; the configurations of this
            // library's trees are what Table II compares.
            const bool ours = std::string(Lib::kName).rfind("Vdb", 0) == 0;
            headers.push_back(ours ? std::string(Lib::kName) + " " + Lib::kConfig : Lib::kName);
        });
        const size_t vdb = size_t(std::find(libs.begin(), libs.end(), "Vdb") - libs.begin());
        const size_t twin =
            size_t(std::find(libs.begin(), libs.end(), "OpenVdbTwin") - libs.begin());
        vdb::bench::RatioRange lookups, sequential, insertion, memory, noise;

        // The per-library figures of a row, NaN where a library has none.
        using Figures = std::vector<double>;
        const auto figures = [&](const ByLib* byLib, auto metric) {
            Figures out(libs.size(), kMissing);
            for (size_t i = 0; byLib && i < libs.size(); ++i)
                if (const auto it = byLib->find(libs[i]); it != byLib->end())
                    out[i] = metric(it->second);
            return out;
        };
        const auto has = [](const Figures& f) {
            return std::any_of(f.begin(), f.end(), [](double v) { return std::isfinite(v); });
        };
        // "3.87 (1.21)": a figure and its ratio to OpenVdb's, the Vdb ratio in bold; adds the
        // Vdb ratio to `range` and the OpenVdbTwin ratio to `twinRange` unless they are null.
        const auto row = [&](const std::string& label, const Figures& f, int decimals, bool ratios,
                             vdb::bench::RatioRange* range, vdb::bench::RatioRange* twinRange) {
            MarkdownRow cells{label, vdb::bench::fmt(f[0], decimals)};
            for (size_t i = 1; i < f.size(); ++i) {
                std::string cell = vdb::bench::fmt(f[i], decimals);
                const double ratio = f[i] / f[0];
                if (ratios && std::isfinite(ratio)) {
                    const std::string text = vdb::bench::fmt(ratio, 2);
                    cell += " (" + (i == vdb ? "**" + text + "**" : text) + ")";
                }
                cells.push_back(cell);
            }
            if (ratios && range && vdb < f.size())
                range->add(f[vdb] / f[0]);
            if (ratios && twinRange && twin < f.size())
                twinRange->add(f[twin] / f[0]);
            return cells;
        };

        const std::string tableTwo =
            std::to_string(kProbeCount) + "/" + std::to_string(kTableTwoRunLength);
        const std::string roundRobin = std::to_string(kProbeCount) + "/1";
        const std::string random = std::to_string(kLookups);
        const auto lookupFigures = [&](const std::string& op) {
            return figures(timesOf(op), nsPerOp);
        };
        const Figures cachedTableTwo = lookupFigures("BM_CachedLookup/" + tableTwo);
        const Figures topDownTableTwo = lookupFigures("BM_TopDownLookup/" + tableTwo);
        std::vector<MarkdownRow> lookupRows;
        const size_t indexed =
            size_t(std::find(libs.begin(), libs.end(), "VdbIndexed") - libs.begin());
        vdb::bench::RatioRange indexedLookups;
        const auto addLookup = [&](const std::string& label, const Figures& f) {
            if (!has(f))
                return;
            lookupRows.push_back(row(label, f, 2, true, &lookups, &noise));
            if (indexed < f.size() && std::isfinite(f[indexed] / f[0]))
                indexedLookups.add(f[indexed] / f[0]);
        };
        addLookup("cached, Table II (`/" + tableTwo + "`)", cachedTableTwo);
        addLookup("top-down, Table II (`/" + tableTwo + "`)", topDownTableTwo);
        if (has(cachedTableTwo) && has(topDownTableTwo)) {
            Figures quotient;
            for (size_t i = 0; i < libs.size(); ++i)
                quotient.push_back(topDownTableTwo[i] / cachedTableTwo[i]);
            lookupRows.push_back(row("top-down / cached", quotient, 1, false, nullptr, nullptr));
        }
        addLookup("cached, round-robin (`/" + roundRobin + "`)",
                  lookupFigures("BM_CachedLookup/" + roundRobin));
        addLookup("top-down, round-robin (`/" + roundRobin + "`)",
                  lookupFigures("BM_TopDownLookup/" + roundRobin));
        addLookup("cached, 10^7 random voxels", lookupFigures("BM_CachedRandomLookup/" + random));
        addLookup("top-down, 10^7 random voxels",
                  lookupFigures("BM_TopDownRandomLookup/" + random));

        std::vector<MarkdownRow> otherRows;
        const auto addTimed = [&](const std::string& label, const std::string& op,
                                  vdb::bench::RatioRange& range) {
            const Figures f = figures(timesOf(op), nsPerOp);
            if (has(f))
                otherRows.push_back(row(label, f, 2, true, &range, &noise));
        };
        addTimed("sequential, value iterator", "BM_ValueIteration", sequential);
        addTimed("sequential, leaves + value mask", "BM_LeafIteration", sequential);
        addTimed("random insertion, accessor", "BM_RandomInsert", insertion);
        addTimed("random insertion, top-down", "BM_RandomInsertTopDown", insertion);
        if (const Figures f = figures(timesOf("BM_LeafIndexBuild"), nsPerOp); has(f))
            otherRows.push_back(row("`buildLeafIndex()`, per leaf", f, 2, false, nullptr, nullptr));
        // Memory comes from the single run of BM_MemUsage.
        const ByLib* memoryRun = nullptr;
        if (const auto run = mResults.find("run"); run != mResults.end())
            if (const auto op = run->second.find("BM_MemUsage"); op != run->second.end())
                memoryRun = &op->second;
        const auto memoryFigures = [&](const char* name) {
            return figures(memoryRun, [name](const Result& r) {
                const double v = counter(r, name);
                return v >= 0 ? v : kMissing;
            });
        };
        if (const Figures f = memoryFigures("memUsage_MB"); has(f))
            otherRows.push_back(row("`memUsage()`", f, 2, true, &memory, nullptr));
        if (const Figures f = memoryFigures("rss_MB"); has(f))
            otherRows.push_back(row("RSS growth while building", f, 2, true, nullptr, nullptr));
        if (const Figures f = memoryFigures("B/voxel"); has(f))
            otherRows.push_back(
                row("bytes per active voxel (`memUsage`)", f, 2, false, nullptr, nullptr));

        const std::string protocol =
            mRepetitions > 1 ? "median of " + std::to_string(mRepetitions) + " repetitions"
                             : "single runs";
        const double wait = worstWait();
        char note[256];
        if (wait > 1.05)
            std::snprintf(note, sizeof note,
                          "Wall-clock time exceeded CPU time by up to %.0f%% in this run: other "
                          "processes competed for the CPU; read the OpenVdbTwin column (the "
                          "noise floor) first.",
                          100.0 * (wait - 1.0));
        else
            std::snprintf(note, sizeof note,
                          "Wall-clock time was within 5%% of CPU time for every result.");
        if (!lookupRows.empty()) {
            md.paragraph("## Table II: random lookup");
            md.paragraph("CPU nanoseconds per lookup (" + protocol +
                         "); in brackets the ratio to OpenVdb, in bold for Vdb. " + note);
            MarkdownRow header{"Lookup"};
            header.insert(header.end(), headers.begin(), headers.end());
            md.table(header, lookupRows);
            addLookupFloors(md, libs, tableTwo, roundRobin, random);
        }
        if (!otherRows.empty()) {
            md.paragraph("## Other operations");
            md.paragraph("CPU nanoseconds per voxel (" + protocol +
                         "), memory in MiB (one run); in brackets the ratio to OpenVdb.");
            MarkdownRow header{"Operation"};
            header.insert(header.end(), libs.begin(), libs.end());
            md.table(header, otherRows);
            // The floors of the two iterations, each with Vdb's two times over it.
            const Figures f = figures(timesOf("BM_ValueIteration"), nsPerOp);
            const Figures g = figures(timesOf("BM_LeafIteration"), nsPerOp);
            const auto vdbColumn = std::find(libs.begin(), libs.end(), std::string(Vdb::kName));
            const size_t v = size_t(vdbColumn - libs.begin());
            std::vector<MarkdownRow> floorRows;
            for (const auto& [op, what] :
                 {std::pair{"BM_ArraySum",
                            "the active values in one array, summed the same "
                            "way (into a double, in order)"},
                  std::pair{"BM_LeafBytesSum",
                            "every value of the leaves (the bytes the "
                            "iterations stream) in one array, summed the "
                            "same way"},
                  std::pair{"BM_LeafBytesStream",
                            "the same bytes at memory speed (sixteen "
                            "independent sums)"}}) {
                const ByLib* floor = timesOf(op);
                const auto it = floor ? floor->find(Floor::kName) : ByLib::const_iterator{};
                if (!floor || it == floor->end() || !std::isfinite(nsPerOp(it->second)))
                    continue;
                const double ns = nsPerOp(it->second);
                MarkdownRow row{what, vdb::bench::fmt(ns, 2)};
                const bool have = v < libs.size() && std::isfinite(f[v]) && std::isfinite(g[v]);
                row.push_back(have ? vdb::bench::fmt(f[v] / ns, 2) : "-");
                row.push_back(have ? vdb::bench::fmt(g[v] / ns, 2) : "-");
                const auto bytes = it->second.counters.find("bytes");
                if (bytes != it->second.counters.end() && it->second.cpuNs > 0)
                    row[0] +=
                        " (" + vdb::bench::fmt(bytes->second / it->second.cpuNs, 1) + " GB/s)";
                floorRows.push_back(row);
            }
            if (!floorRows.empty()) {
                md.paragraph(
                    "Floors of the two iterations, CPU nanoseconds per active voxel, "
                    "and Vdb's times over each:");
                md.table({"Floor", "ns", "value iterator / floor", "leaves + mask / floor"},
                         floorRows);
            }
        }

        // The overview names only what ran (a --benchmark_filter run leaves some out).
        std::string ranges;
        for (const auto& [name, range] :
             {std::pair{"lookups", &lookups}, std::pair{"lookups with leaf index", &indexedLookups},
              std::pair{"sequential", &sequential}, std::pair{"insertion", &insertion},
              std::pair{"memory", &memory}})
            if (!range->empty())
                ranges += (ranges.empty() ? "" : ", ") + range->status(name);
        if (!ranges.empty())
            md.status(ranges);
        if (!noise.empty())
            md.status(noise.status("OpenVdbTwin noise"));
    }

private:
    using ByLib = std::map<std::string, Result>;
    using ByOp = std::map<std::string, ByLib>;
    using MarkdownRow = vdb::bench::MarkdownReport::Row;

    /// The table of the lookups' floors: each lookup beside the same loop with the tree
    /// replaced by one array read.
    void addLookupFloors(vdb::bench::MarkdownReport& md, const std::vector<std::string>& libs,
                         const std::string& tableTwo, const std::string& roundRobin,
                         const std::string& random) const {
        const auto nsOf = [this](const std::string& op, const char* lib) {
            const ByLib* byLib = timesOf(op);
            const auto it = byLib ? byLib->find(lib) : ByLib::const_iterator{};
            return byLib && it != byLib->end() ? nsPerOp(it->second) : kMissing;
        };
        if (std::find(libs.begin(), libs.end(), std::string(Vdb::kName)) == libs.end())
            return;
        std::vector<MarkdownRow> rows;
        for (const auto& [label, lookup, floor] :
             {std::tuple{"cached, Table II", "BM_CachedLookup/" + tableTwo,
                         "BM_LookupFloor/" + tableTwo},
              std::tuple{"top-down, Table II", "BM_TopDownLookup/" + tableTwo,
                         "BM_LookupFloor/" + tableTwo},
              std::tuple{"cached, round-robin", "BM_CachedLookup/" + roundRobin,
                         "BM_LookupFloor/" + roundRobin},
              std::tuple{"top-down, round-robin", "BM_TopDownLookup/" + roundRobin,
                         "BM_LookupFloor/" + roundRobin},
              std::tuple{"cached, 10^7 random voxels", "BM_CachedRandomLookup/" + random,
                         "BM_RandomLookupFloor/" + random},
              std::tuple{"top-down, 10^7 random voxels", "BM_TopDownRandomLookup/" + random,
                         "BM_RandomLookupFloor/" + random}}) {
            const double base = nsOf(floor, Floor::kName);
            const double theirs = nsOf(lookup, OpenVdb::kName);
            const double ours = nsOf(lookup, Vdb::kName);
            const double indexed = nsOf(lookup, VdbIndexed::kName);
            if (!std::isfinite(base) || !std::isfinite(theirs) || !std::isfinite(ours))
                continue;
            rows.push_back({label, vdb::bench::fmt(base, 2), vdb::bench::fmt(base / theirs, 2),
                            vdb::bench::fmt(ours / theirs, 2),
                            vdb::bench::fmt(indexed / theirs, 2)});
        }
        if (rows.empty())
            return;
        md.paragraph(
            "Floors of the lookups, CPU nanoseconds per lookup: the same loop with the tree "
            "replaced by one array read (Table II and round-robin: the coordinates read the "
            "same way and the value at their leaf offset in one leaf's values; random: each "
            "voxel's value read from one array of every leaf value at an index computed "
            "beforehand). Floor / OpenVdb is the lowest ratio any library could reach.");
        md.table({"Lookup", "floor ns", "floor / OpenVdb", "Vdb / OpenVdb", "VdbIndexed / OpenVdb"},
                 rows);
    }

    static constexpr double kMissing = std::numeric_limits<double>::quiet_NaN();

    /// The results of `op` per library: the medians over the repetitions, or the single runs
    /// where there was one repetition; null when `op` did not run.
    const ByLib* timesOf(const std::string& op) const {
        for (const char* stat : {"median", "run"}) {
            const auto found = mResults.find(stat);
            if (found == mResults.end())
                continue;
            const auto byOp = found->second.find(op);
            if (byOp != found->second.end())
                return &byOp->second;
        }
        return nullptr;
    }

    /// The largest wall-clock / CPU time of any result, at least 1.
    double worstWait() const {
        double wait = 1.0;
        for (const auto& [stat, byOp] : mResults)
            for (const auto& [op, byLib] : byOp)
                for (const auto& [lib, r] : byLib)
                    if (r.cpuNs > 0)
                        wait = std::max(wait, r.realNs / r.cpuNs);
        return wait;
    }

    // Prints the times of `times`, and the memory rows of `singles` unless it is null.
    static void printTable(const std::vector<std::string>& rows, const ByOp& times,
                           const ByOp* singles) {
        std::vector<std::string> libs;
        forEachLibrary([&](auto lib) { libs.push_back(decltype(lib)::type::kName); });
        std::printf("%-40s %9s", "operation", libs[0].c_str());
        for (size_t i = 1; i < libs.size(); ++i)
            std::printf(" %12s %5s", libs[i].c_str(), "ratio");
        std::printf("\n");
        for (const std::string& op : rows) {
            if (op.rfind("BM_MemUsage", 0) == 0) {
                if (!singles || singles->count(op) == 0)
                    continue;
                printRow("memUsage (MB)", singles->at(op), libs,
                         [](const Result& r) { return counter(r, "memUsage_MB"); });
                printRow("RSS growth while building (MB)", singles->at(op), libs,
                         [](const Result& r) { return counter(r, "rss_MB"); });
                continue;
            }
            if (times.count(op) == 0)
                continue;
            // The console marks a missing figure with a negative one.
            const auto shown = [](const Result& r) {
                const double ns = nsPerOp(r);
                return std::isfinite(ns) ? ns : -1.0;
            };
            const ByLib& byLib = times.at(op);
            if (const auto floor = byLib.find(Floor::kName); floor != byLib.end()) {
                // A floor has no library: its time goes in the first column.
                std::printf("%-40s %9s  (floor)\n", op.c_str(),
                            format(shown(floor->second)).c_str());
                continue;
            }
            printRow(op, byLib, libs, shown);
        }
    }

    /// CPU nanoseconds per operation of `r`; NaN when it counted no operation.
    static double nsPerOp(const Result& r) {
        const double ops = counter(r, "ops");
        return ops > 0 ? r.cpuNs / ops : kMissing;
    }

    static double counter(const Result& r, const char* name) {
        const auto it = r.counters.find(name);
        return it == r.counters.end() ? -1.0 : it->second.value;
    }

    template <typename Metric>
    static void printRow(const std::string& label, const ByLib& byLib,
                         const std::vector<std::string>& libs, Metric metric) {
        std::vector<double> value;
        for (const std::string& lib : libs) {
            const auto it = byLib.find(lib);
            value.push_back(it == byLib.end() ? -1.0 : metric(it->second));
        }
        std::printf("%-40s %9s", label.c_str(), format(value[0]).c_str());
        for (size_t i = 1; i < libs.size(); ++i) {
            const bool ratio = value[0] > 0 && value[i] >= 0;
            std::printf(" %12s %5s", format(value[i]).c_str(),
                        ratio ? format(value[i] / value[0], 2).c_str() : "-");
        }
        std::printf("\n");
    }

    static std::string format(double v, int decimals = 3) {
        if (v < 0)
            return "-";
        char text[32];
        std::snprintf(text, sizeof text, "%.*f", decimals, v);
        return text;
    }

    std::map<std::string, ByOp> mResults;  // statistic -> operation -> library
    std::vector<std::string> mRows;
    int64_t mRepetitions = 0;  // the most repetitions of any kept result
};

// Prints the statistics of the shared tree of `Lib` if it was built; returns false when that
// tree failed its check.
template <typename Lib>
bool printTreeStats() {
    if (!sharedTreeBuilt<Lib>)
        return true;
    const auto& shared = sharedTree<Lib>();
    const auto& tree = *shared.tree;
    std::printf("%-13s %-13s leaves %7llu  internal %5llu  memUsage %8.2f MB  %6.2f B/voxel%s%s\n",
                Lib::kName, Lib::kConfig, (unsigned long long)tree.leafCount(),
                (unsigned long long)tree.nonLeafCount(), double(tree.memUsage()) / (1 << 20),
                double(tree.memUsage()) / double(inputs().band.size()),
                shared.error.empty() ? "" : "  ERROR: ", shared.error.c_str());
    return shared.error.empty();
}

/// The node counts of one library's shared tree, for the report.
struct TreeShape {
    std::string name;
    uint64_t leaves = 0, internal = 0;
};

// Appends the shape of the shared tree of `Lib` to `shapes` if that tree was built.
template <typename Lib>
void addTreeShape(std::vector<TreeShape>& shapes) {
    if (!sharedTreeBuilt<Lib>)
        return;
    const auto& tree = *sharedTree<Lib>().tree;
    shapes.push_back({Lib::kName, uint64_t(tree.leafCount()), uint64_t(tree.nonLeafCount())});
}

/// "Band of N active voxels at R^3; ..." with the node counts of the trees that the lookups
/// read: once when all trees agree, per library otherwise.
std::string bandParagraph() {
    using vdb::bench::fmt;
    std::string text = "Band of " + fmt(double(inputs().band.size()), 0) + " active voxels at " +
                       std::to_string(kResolution) + "^3";
    std::vector<TreeShape> shapes;
    forEachLibrary([&](auto lib) { addTreeShape<typename decltype(lib)::type>(shapes); });
    if (shapes.empty())
        return text + ".";
    const auto nodes = [](const TreeShape& s) {
        return fmt(double(s.leaves), 0) + " leaves and " + fmt(double(s.internal), 0) +
               " internal nodes";
    };
    const bool same = std::all_of(shapes.begin(), shapes.end(), [&](const TreeShape& s) {
        return s.leaves == shapes[0].leaves && s.internal == shapes[0].internal;
    });
    if (same)
        return text + "; every tree that the lookups and iterations read has " + nodes(shapes[0]) +
               ".";
    text += "; the trees that the lookups and iterations read have";
    for (size_t i = 0; i < shapes.size(); ++i)
        text += (i ? ", " : " ") + shapes[i].name + " " + nodes(shapes[i]);
    return text + ".";
}

}  // namespace

int main(int argc, char** argv) {
    // Defaults: 5 repetitions, run in random order so that drifting machine load spreads over
    // all libraries, with only their aggregates on screen. Flags given on the command line come
    // later and win. --markdown FILE is this program's own option, which Google Benchmark
    // would reject as unrecognized.
    std::string repetitions = "--benchmark_repetitions=5";
    std::string interleave = "--benchmark_enable_random_interleaving=true";
    std::string aggregates = "--benchmark_display_aggregates_only=true";
    std::vector<char*> args{argv[0], repetitions.data(), interleave.data(), aggregates.data()};
    std::string markdownPath;
    vdb::bench::Options options("vdb_bench_tree [--markdown FILE] [Google Benchmark flags]");
    options.text("--markdown", markdownPath);
    options.parse(argc, argv, &args);
    int count = int(args.size());
    args.push_back(nullptr);
    benchmark::Initialize(&count, args.data());
    if (benchmark::ReportUnrecognizedArguments(count, args.data()))
        return 1;

    openvdb::initialize();
    const auto& in = inputs();
    std::printf("Enright sphere band at %d^3: %zu active voxels (paper: %llu)\n", kResolution,
                in.band.size(), (unsigned long long)EnrightSphere::paperActiveVoxels(kResolution));
    std::fflush(stdout);

    registerBenchmarks();
    SummaryReporter reporter;
    benchmark::RunSpecifiedBenchmarks(&reporter);
    reporter.printSummary();
    std::printf("\nTrees read by the lookup and iteration benchmarks:\n");
    bool ok = true;
    forEachLibrary([&](auto lib) { ok &= printTreeStats<typename decltype(lib)::type>(); });
    benchmark::Shutdown();
    if (!markdownPath.empty()) {
        vdb::bench::MarkdownReport md;
        md.paragraph(bandParagraph());
        reporter.addMarkdown(md);
        if (!ok)
            md.status("a tree failed its check");
        ok &= md.write(markdownPath);
    }
    return ok ? 0 : 1;
}
