// SPDX-License-Identifier: Apache-2.0
// Delayed (out-of-core) loading: grids opened with open(true) hold their topology, and each
// leaf loads its values on first access. The oracle is the same file read eagerly: every
// voxel and tile must agree bit for bit, for every grid type and codec; memory before the
// first access is a small fraction; many threads touching the same leaves at once load each
// leaf exactly once (this file also runs under ThreadSanitizer: scripts/test tsan); a file
// removed, replaced or truncated after opening never crashes.

#include <vdb/Grid.h>
#include <vdb/io/Archive.h>
#include <vdb/io/File.h>

#include <GridContents.h>
#include <Oracles.h>
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <atomic>
#include <barrier>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace vdb {
namespace {

namespace fs = std::filesystem;

std::string tempPath(const std::string& name) {
    return test::tempPath("vdb_delayed_test_", name);
}

/// Checks that two trees hold the same voxels and tiles (boxes, levels, states, value bits).
template <typename TreeT>
::testing::AssertionResult sameTrees(const TreeT& a, const TreeT& b) {
    if (!test::sameBits(a.background(), b.background()))
        return ::testing::AssertionFailure() << "backgrounds differ";
    const auto ia = test::treeContents(a);
    const auto ib = test::treeContents(b);
    if (ia.size() != ib.size())
        return ::testing::AssertionFailure() << ia.size() << " values vs " << ib.size();
    for (size_t i = 0; i < ia.size(); ++i) {
        const auto &x = ia[i], &y = ib[i];
        if (x.min != y.min || x.max != y.max || x.level != y.level || x.active != y.active ||
            !test::sameBits(x.value, y.value))
            return ::testing::AssertionFailure() << "item " << i << " at " << x.min << " differs";
    }
    return ::testing::AssertionSuccess();
}

template <typename TreeT>
size_t outOfCoreLeafCount(const TreeT& tree) {
    size_t n = 0;
    for (auto it = tree.cbeginLeaf(); it; ++it) {
        if constexpr (requires { it->isOutOfCore(); })
            n += it->isOutOfCore() ? 1 : 0;
    }
    return n;
}

/// The grid named "g" of `path`, read with or without delayed loading.
template <typename GridT>
typename GridT::Ptr readG(const std::string& path, bool delayed) {
    io::File in(path);
    in.open(delayed);
    return gridPtrCast<GridT>(in.readGrid("g"));
}

/// Runs TBB serially: the threads of these tests are their own std::threads, and the
/// ThreadSanitizer run (scripts/test tsan) would report false races inside the uninstrumented
/// TBB library otherwise.
class DelayedLoadTest : public ::testing::Test {
    tbb::global_control mSerial{tbb::global_control::max_allowed_parallelism, 1};
};

template <typename GridT>
class DelayedLoad : public DelayedLoadTest {};

using AllGrids = ::testing::Types<FloatGrid, DoubleGrid, Int32Grid, Int64Grid, BoolGrid, MaskGrid,
                                  Vec3SGrid, Vec3DGrid, Vec3IGrid>;
TYPED_TEST_SUITE(DelayedLoad, AllGrids);

TYPED_TEST(DelayedLoad, ValuesEqualEagerLoadingForEveryCodec) {
    using GridT = TypeParam;
    using ValueT = typename GridT::ValueType;
    constexpr bool HAS_VALUES = !std::is_same_v<ValueT, bool> && !std::is_same_v<ValueT, ValueMask>;
    auto grid = GridT::create(test::randomValue<ValueT>(3u));
    test::fillTestGrid(*grid, 5);
    grid->setName("g");
    const std::string path = tempPath("codecs_" + grid->valueType() + ".vdb");
    // Every codec, and half floats with the two codings of inactive values (the half rules of
    // FORMAT.md 1.9 are tested through both readers in FileTest).
    const std::pair<uint32_t, bool> settings[] = {
        {io::COMPRESS_NONE, false},  {io::COMPRESS_ACTIVE_MASK, false},
        {io::COMPRESS_ZIP, false},   {io::COMPRESS_ZIP | io::COMPRESS_ACTIVE_MASK, false},
        {io::COMPRESS_BLOSC, false}, {io::COMPRESS_BLOSC | io::COMPRESS_ACTIVE_MASK, false},
        {io::COMPRESS_NONE, true},   {io::COMPRESS_BLOSC | io::COMPRESS_ACTIVE_MASK, true}};
    for (const auto& [flags, half] : settings) {
        SCOPED_TRACE("flags " + std::to_string(flags) + (half ? " half" : ""));
        grid->setSaveFloatAsHalf(half);
        io::File out(path);
        out.setCompression(flags);
        out.write({grid});
        const auto eager = readG<GridT>(path, false);
        const auto delayed = readG<GridT>(path, true);
        ASSERT_TRUE(eager && delayed);
        EXPECT_EQ(outOfCoreLeafCount(eager->tree()), 0u);
        const size_t leaves = delayed->tree().leafCount();
        ASSERT_GT(leaves, 10u);
        EXPECT_EQ(outOfCoreLeafCount(delayed->tree()), HAS_VALUES ? leaves : 0u);
        // Topology queries do not load values.
        EXPECT_EQ(delayed->activeVoxelCount(), eager->activeVoxelCount());
        EXPECT_EQ(delayed->evalActiveVoxelBoundingBox(), eager->evalActiveVoxelBoundingBox());
        EXPECT_EQ(outOfCoreLeafCount(delayed->tree()), HAS_VALUES ? leaves : 0u);
        EXPECT_TRUE(sameTrees(eager->tree(), delayed->tree()));
        EXPECT_EQ(outOfCoreLeafCount(delayed->tree()), 0u);
    }
}

TEST_F(DelayedLoadTest, EveryAccessPathLoadsTheValues) {
    auto grid = FloatGrid::create(-1.5f);
    test::fillTestGrid(*grid, 8);
    grid->setName("g");
    const std::string path = tempPath("paths.vdb");
    io::File(path).write({grid});
    const auto eager = readG<FloatGrid>(path, false);
    const Coord dense(400, 400, 400);  // a leaf of fillTestGrid with every voxel active

    // Const accessor, tree getValue, probeValue.
    auto g = readG<FloatGrid>(path, true);
    EXPECT_EQ(g->getConstAccessor().getValue(dense), eager->tree().getValue(dense));
    EXPECT_EQ(g->tree().getValue(dense + Coord(1, 2, 3)),
              eager->tree().getValue(dense + Coord(1, 2, 3)));
    float v = 0;
    EXPECT_TRUE(g->tree().probeValue(dense, v));
    EXPECT_EQ(v, eager->tree().getValue(dense));

    // A write to an out-of-core leaf keeps the other values.
    g = readG<FloatGrid>(path, true);
    g->tree().setValueOnly(dense, 42.0f);
    auto expected = eager->deepCopy();
    expected->tree().setValueOnly(dense, 42.0f);
    EXPECT_TRUE(sameTrees(expected->tree(), g->tree()));

    // State changes before the load do not change the values.
    g = readG<FloatGrid>(path, true);
    auto* leaf = g->tree().probeLeaf(dense);
    ASSERT_TRUE(leaf && leaf->isOutOfCore());
    leaf->setValueOff(Index(5));
    leaf->getValueMask().setOff(Index(6));
    EXPECT_TRUE(leaf->isOutOfCore());
    expected = eager->deepCopy();
    expected->tree().probeLeaf(dense)->setValueOff(Index(5));
    expected->tree().probeLeaf(dense)->setValueOff(Index(6));
    EXPECT_TRUE(sameTrees(expected->tree(), g->tree()));

    // Copies stay out of core and load on their own.
    g = readG<FloatGrid>(path, true);
    const auto copy = g->deepCopy();
    EXPECT_EQ(outOfCoreLeafCount(copy->tree()), g->tree().leafCount());
    EXPECT_TRUE(sameTrees(eager->tree(), copy->tree()));
    EXPECT_EQ(outOfCoreLeafCount(g->tree()), g->tree().leafCount());

    // Value iterators writing through, buffers, temporal buffers, fill.
    g = readG<FloatGrid>(path, true);
    for (auto it = g->tree().beginValueOn(); it; ++it)
        it.setValue(*it + 1.0f);
    expected = eager->deepCopy();
    for (auto it = expected->tree().beginValueOn(); it; ++it)
        it.setValue(*it + 1.0f);
    EXPECT_TRUE(sameTrees(expected->tree(), g->tree()));
    g = readG<FloatGrid>(path, true);
    leaf = g->tree().probeLeaf(dense);
    leaf->setBufferCount(2);
    EXPECT_EQ(leaf->buffer(1)[7], eager->tree().probeConstLeaf(dense)->getValue(Index(7)));
    g = readG<FloatGrid>(path, true);
    leaf = g->tree().probeLeaf(dense);
    leaf->fill(3.0f, true);
    EXPECT_FALSE(leaf->isOutOfCore());
    EXPECT_EQ(leaf->getValue(Index(100)), 3.0f);

    // Writing a delayed grid writes the file's values.
    g = readG<FloatGrid>(path, true);
    const std::string again = tempPath("paths_again.vdb");
    io::File(again).write({g});
    EXPECT_TRUE(sameTrees(eager->tree(), readG<FloatGrid>(again, false)->tree()));
}

TEST_F(DelayedLoadTest, MemoryBeforeFirstAccessIsASmallFraction) {
    // A dense block of float leaves: their values dominate the eager grid's memory. The size
    // does not follow the test workload: with fewer leaves the internal nodes would dominate.
    auto grid = FloatGrid::create(0.0f);
    const int n = 12;
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> value(-1.0f, 1.0f);
    auto acc = grid->getAccessor();
    for (int i = 0; i < 8 * n; ++i)
        for (int j = 0; j < 8 * n; ++j)
            for (int k = 0; k < 8 * n; ++k)
                acc.setValue(Coord(i, j, k), value(rng));
    grid->setName("g");
    const std::string path = tempPath("memory.vdb");
    io::File(path).write({grid});
    const auto eager = readG<FloatGrid>(path, false);
    const auto delayed = readG<FloatGrid>(path, true);
    // An out-of-core float leaf holds its node and a record of where its values are: 128 of
    // 2,136 bytes. The grid's internal nodes, here a large share for few leaves, are loaded.
    const auto leafBytes = [](const FloatGrid& g) {
        Index64 n = 0;
        for (auto it = g.tree().cbeginLeaf(); it; ++it)
            n += it->memUsage();
        return n;
    };
    const double leafFraction = double(leafBytes(*delayed)) / double(leafBytes(*eager));
    EXPECT_LT(leafFraction, 0.07) << leafBytes(*delayed) << " of " << leafBytes(*eager);
    const double fraction = double(delayed->memUsage()) / double(eager->memUsage());
    EXPECT_LT(fraction, 0.15) << delayed->memUsage() << " of " << eager->memUsage() << " bytes";
    EXPECT_TRUE(sameTrees(eager->tree(), delayed->tree()));
    EXPECT_EQ(delayed->memUsage(), eager->memUsage());
}

TEST_F(DelayedLoadTest, ConcurrentFirstAccessLoadsEachLeafOnce) {
    // Every thread reads every voxel of the same out-of-core leaves, each in its own order,
    // starting together; another copies the grid and asks for its memory meanwhile.
    auto grid = FloatGrid::create(0.25f);
    test::fillTestGrid(*grid, 13);
    grid->setName("g");
    const std::string path = tempPath("threads.vdb");
    io::File out(path);
    out.setCompression(io::COMPRESS_BLOSC | io::COMPRESS_ACTIVE_MASK);
    out.write({grid});
    const auto expected = test::treeContents(grid->tree());
    const int rounds = std::max(1, test::scaledBatchCount(10));
    const unsigned threadCount = 8;
    for (int round = 0; round < rounds; ++round) {
        const auto delayed = readG<FloatGrid>(path, true);
        const FloatTree& tree = delayed->tree();
        std::vector<const FloatTree::LeafNodeType*> leaves;
        for (auto it = tree.cbeginLeaf(); it; ++it)
            leaves.push_back(&*it);
        std::barrier start(threadCount + 1);
        std::atomic<size_t> mismatches{0};
        std::vector<std::thread> threads;
        for (unsigned t = 0; t < threadCount; ++t) {
            threads.emplace_back([&, t] {
                std::vector<const FloatTree::LeafNodeType*> order = leaves;
                std::shuffle(order.begin(), order.end(), std::mt19937(t * 7919u + unsigned(round)));
                const auto reference = grid->getConstAccessor();
                start.arrive_and_wait();
                for (const auto* leaf : order) {
                    for (Index n = 0; n < FloatTree::LeafNodeType::NUM_VALUES; n += 1 + t) {
                        const Coord ijk = leaf->offsetToGlobalCoord(n);
                        if (!test::sameBits(leaf->getValue(n), reference.getValue(ijk)))
                            ++mismatches;
                    }
                }
            });
        }
        FloatGrid::Ptr copy;
        Index64 mem = 0;
        threads.emplace_back([&] {
            start.arrive_and_wait();
            copy = delayed->deepCopy();
            mem = delayed->memUsage();
        });
        for (auto& th : threads)
            th.join();
        EXPECT_EQ(mismatches.load(), 0u);
        EXPECT_GT(mem, 0u);
        EXPECT_EQ(outOfCoreLeafCount(tree), 0u);
        const auto got = test::treeContents(copy->tree());
        ASSERT_EQ(got.size(), expected.size());
        for (size_t i = 0; i < got.size(); ++i)
            ASSERT_TRUE(test::sameBits(got[i].value, expected[i].value)) << got[i].min;
    }
}

TEST_F(DelayedLoadTest, LeafIndexServesConcurrentFirstAccessAndDisjointWrites) {
    // A file read with delayed loading gets its leaf index from the topology alone; then threads
    // read through it (top-down and with their own accessors), loading leaves as they go, and
    // afterwards write disjoint leaves through it. The oracle is the grid that was written.
    auto grid = FloatGrid::create(0.25f);
    test::fillTestGrid(*grid, 17);
    grid->setName("g");
    const std::string path = tempPath("index_threads.vdb");
    io::File out(path);
    out.setCompression(io::COMPRESS_BLOSC | io::COMPRESS_ACTIVE_MASK);
    out.write({grid});
    const auto delayed = readG<FloatGrid>(path, true);
    FloatTree& tree = delayed->tree();
    const size_t leafCount = tree.leafCount();
    ASSERT_GT(leafCount, 10u);
    tree.buildLeafIndex();
    ASSERT_TRUE(tree.hasLeafIndex());
    EXPECT_EQ(outOfCoreLeafCount(tree), leafCount);  // the index loads no values
    std::vector<Coord> origins;
    for (auto it = tree.cbeginLeaf(); it; ++it)
        origins.push_back(it->origin());
    const unsigned threadCount = 6;
    std::atomic<size_t> mismatches{0};
    {
        std::barrier start(threadCount);
        std::vector<std::thread> threads;
        for (unsigned t = 0; t < threadCount; ++t) {
            threads.emplace_back([&, t] {
                std::mt19937 rng(t + 1);
                const auto reference = grid->getConstAccessor();
                FloatTree::ConstAccessor acc(std::as_const(tree));
                start.arrive_and_wait();
                for (int n = 0; n < 20000; ++n) {
                    const Coord ijk = origins[rng() % origins.size()].offsetBy(
                        Int32(rng() % 10) - 1, Int32(rng() % 10) - 1, Int32(rng() % 10) - 1);
                    const float expected = reference.getValue(ijk);
                    const float got = n % 2 ? acc.getValue(ijk) : std::as_const(tree).getValue(ijk);
                    if (!test::sameBits(got, expected) ||
                        acc.isValueOn(ijk) != reference.isValueOn(ijk))
                        ++mismatches;
                }
            });
        }
        for (auto& th : threads)
            th.join();
    }
    EXPECT_EQ(mismatches.load(), 0u);
    ASSERT_TRUE(tree.hasLeafIndex());
    // Writes to existing leaves change no topology: each thread writes its own leaves through
    // its accessor, which finds them in the index.
    {
        std::barrier start(threadCount);
        std::vector<std::thread> threads;
        for (unsigned t = 0; t < threadCount; ++t) {
            threads.emplace_back([&, t] {
                FloatTree::Accessor acc(tree);
                start.arrive_and_wait();
                for (size_t i = t; i < origins.size(); i += threadCount)
                    for (Int32 d = 0; d < 8; ++d)
                        acc.setValueOnly(origins[i].offsetBy(d, 7 - d, d), float(i) + float(d));
            });
        }
        for (auto& th : threads)
            th.join();
    }
    EXPECT_TRUE(tree.hasLeafIndex());
    EXPECT_EQ(tree.leafCount(), leafCount);
    for (size_t i = 0; i < origins.size(); ++i)
        for (Int32 d = 0; d < 8; ++d)
            ASSERT_EQ(tree.getValue(origins[i].offsetBy(d, 7 - d, d)), float(i) + float(d));
}

/// A record that counts its loads, fails while `fail` is set, and fills values with `base`.
struct CountingRecord final : FloatTree::LeafNodeType::OutOfCore {
    std::atomic<int>* loads;
    std::atomic<bool>* fail;
    float base;
    CountingRecord(std::atomic<int>* l, std::atomic<bool>* f, float b)
        : loads(l), fail(f), base(b) {}
    void load(float* values) const override {
        if (fail->load())
            throw IoError("cannot load");
        ++*loads;
        for (Index n = 0; n < FloatTree::LeafNodeType::NUM_VALUES; ++n)
            values[n] = base + float(n);
    }
    std::unique_ptr<OutOfCore> clone() const override {
        return std::make_unique<CountingRecord>(*this);
    }
    Index64 memUsage() const override { return sizeof(CountingRecord); }
};

TEST_F(DelayedLoadTest, LeafLoadsOnceAndFailedLoadsCanBeRetried) {
    using LeafT = FloatTree::LeafNodeType;
    std::atomic<int> loads{0};
    std::atomic<bool> fail{true};
    LeafT leaf(tree::PartialCreate{}, Coord(8, 16, 24));
    leaf.setValueOn(Index(3));
    leaf.setOutOfCore(std::make_unique<CountingRecord>(&loads, &fail, 10.0f));
    EXPECT_TRUE(leaf.isOutOfCore());
    EXPECT_TRUE(leaf.isAllocated());
    EXPECT_EQ(leaf.bufferCount(), 1u);
    EXPECT_EQ(leaf.memUsage(), sizeof(LeafT) + sizeof(CountingRecord));
    EXPECT_THROW((void)leaf.getValue(Index(0)), IoError);
    EXPECT_TRUE(leaf.isOutOfCore());
    fail = false;

    const LeafT copy(leaf);
    EXPECT_TRUE(copy.isOutOfCore());
    std::barrier start(8);
    std::vector<std::thread> threads;
    std::atomic<int> wrong{0};
    for (int t = 0; t < 8; ++t) {
        threads.emplace_back([&, t] {
            start.arrive_and_wait();
            for (Index n = Index(t); n < LeafT::NUM_VALUES; n += 8)
                wrong += leaf.getValue(n) == 10.0f + float(n) ? 0 : 1;
        });
    }
    for (auto& th : threads)
        th.join();
    EXPECT_EQ(wrong.load(), 0);
    EXPECT_EQ(loads.load(), 1);
    EXPECT_FALSE(leaf.isOutOfCore());
    EXPECT_TRUE(leaf.isValueOn(Index(3)));
    EXPECT_EQ(leaf.memUsage(), sizeof(LeafT) + LeafT::NUM_VALUES * sizeof(float));
    EXPECT_EQ(copy.getValue(Index(9)), 19.0f);
    EXPECT_EQ(loads.load(), 2);

    LeafT dropped(tree::PartialCreate{}, Coord(0));
    dropped.setOutOfCore(std::make_unique<CountingRecord>(&loads, &fail, 0.0f));
    dropped.fill(2.0f, false);
    EXPECT_EQ(dropped.getValue(Index(1)), 2.0f);
    EXPECT_EQ(loads.load(), 2);  // fill() does not read what it overwrites
}

TEST_F(DelayedLoadTest, GridsOutliveTheFileObject) {
    auto grid = Vec3SGrid::create(Vec3s(0.0f));
    test::fillTestGrid(*grid, 17);
    grid->setName("g");
    const std::string path = tempPath("outlive.vdb");
    io::File(path).write({grid});
    GridPtrVecPtr grids;
    {
        io::File in(path);
        in.open();
        grids = in.getGrids();
        in.close();
    }
    ASSERT_EQ(grids->size(), 1u);
    EXPECT_TRUE(sameTrees(grid->tree(), gridPtrCast<Vec3SGrid>(grids->at(0))->tree()));
}

TEST_F(DelayedLoadTest, RemovedReplacedAndTruncatedFilesNeverCrash) {
    auto grid = FloatGrid::create(1.0f);
    test::fillTestGrid(*grid, 23);
    grid->setName("g");
    const std::string path = tempPath("changed.vdb");
    io::File(path).write({grid});

    // Removed after reading the grid: the open descriptor still serves the bytes.
    auto removed = readG<FloatGrid>(path, true);
    fs::remove(path);
    EXPECT_TRUE(sameTrees(grid->tree(), removed->tree()));

    // Replaced by a new file (write() renames into place): the old bytes are served.
    io::File(path).write({grid});
    auto replaced = readG<FloatGrid>(path, true);
    auto other = FloatGrid::create(7.0f);
    other->tree().setValueOn(Coord(1, 2, 3), 5.0f);
    other->setName("g");
    io::File(path).write({other});
    EXPECT_TRUE(sameTrees(grid->tree(), replaced->tree()));

    // Truncated in place: the accesses that need missing bytes raise IoError.
    io::File(path).write({grid});
    io::File in(path);
    in.open();
    auto truncated = gridPtrCast<FloatGrid>(in.readGrid("g"));
    fs::resize_file(path, 200);
    int errors = 0;
    for (auto it = truncated->tree().cbeginLeaf(); it; ++it) {
        try {
            (void)it->getValue(Index(0));
        } catch (const IoError& e) {
            EXPECT_NE(std::string(e.what()).find("changed.vdb"), std::string::npos) << e.what();
            ++errors;
        }
    }
    EXPECT_EQ(errors, int(truncated->tree().leafCount()));
    EXPECT_THROW(in.readGrid("g"), IoError);  // the mapping is not read past the new end
}

}  // namespace
}  // namespace vdb
