// SPDX-License-Identifier: Apache-2.0
// vdb.tools: filtering (LevelSetFilter, Filter), the differential operators of GridOperators.h
// and the level set measures, with OpenVDB's names, for the grid types the C++ library
// instantiates them for.

#include <vdb/GridTypes.h>
#include <vdb/math/FiniteDifference.h>
#include <vdb/tools/Filter.h>
#include <vdb/tools/GridOperators.h>
#include <vdb/tools/LevelSetFilter.h>
#include <vdb/tools/LevelSetMeasure.h>

#include "Common.h"
#include "TreeBlocks.h"

#include <memory>
#include <string>
#include <variant>

namespace vdb::python {

namespace {

/// Throws ValueError when `mask` and `grid` share one tree (the filter would read what it
/// writes).
template <typename GridT>
void checkMaskTree(const GridT& grid, const FloatGrid* mask, const char* op) {
    if constexpr (std::is_same_v<GridT, FloatGrid>) {
        if (mask && mask->treePtr() == grid.treePtr())
            throw py::value_error(std::string(op) + ": the mask shares the filtered grid's tree");
    }
}

// ---- LevelSetFilter

/// The settings of a Python LevelSetFilter; a C++ filter is made from them for each operation,
/// so changes to the grid's transform or topology between calls are always seen.
struct LevelSetFilterSettings {
    math::BiasedGradientScheme spatial = math::HJWENO5_BIAS;
    math::TemporalIntegrationScheme temporal = math::TVD_RK1;
    int normCount = int(tools::LEVEL_SET_HALF_WIDTH);
    float minMask = 0.0f, maxMask = 1.0f;
    bool invert = false;
};

template <typename GridT>
struct LevelSetFilterOf {
    using FilterT = tools::LevelSetFilter<GridT, FloatGrid>;
    typename GridT::Ptr grid;

    /// Runs `fn(filter)` on a filter with `s`'s settings, without the GIL.
    template <typename FnT>
    void run(const LevelSetFilterSettings& s, const FloatGrid* mask, const char* op,
             const FnT& fn) {
        checkUnpinned(&grid->tree(), op);
        checkMaskTree(*grid, mask, op);
        py::gil_scoped_release release;
        FilterT filter(*grid);
        filter.setSpatialScheme(s.spatial);
        filter.setTemporalScheme(s.temporal);
        filter.setNormCount(s.normCount);
        filter.setMaskRange(s.minMask, s.maxMask);
        filter.invertMask(s.invert);
        fn(filter);
    }
};

class PyLevelSetFilter {
public:
    template <typename GridT>
    PyLevelSetFilter(std::in_place_type_t<GridT>, typename GridT::Ptr grid)
        : mImpl(LevelSetFilterOf<GridT>{grid}) {
        tools::LevelSetFilter<GridT, FloatGrid> check(*grid);  // ValueError for a bad grid
    }

    template <typename FnT>
    void run(const FloatGrid* mask, const char* op, const FnT& fn) {
        std::visit([&](auto& impl) { impl.run(mSettings, mask, op, fn); }, mImpl);
    }
    GridBase::Ptr grid() const {
        return std::visit([](const auto& impl) { return GridBase::Ptr(impl.grid); }, mImpl);
    }
    LevelSetFilterSettings& settings() { return mSettings; }

private:
    std::variant<LevelSetFilterOf<FloatGrid>, LevelSetFilterOf<DoubleGrid>> mImpl;
    LevelSetFilterSettings mSettings;
};

/// One constructor `P(grid)` for each of the grid types of the TypeList GridListT, each holding
/// the grid as the variant alternative of its type.
template <typename P, typename GridListT>
void defGridConstructors(py::class_<P>& c) {
    GridListT::forEach([&]<typename GridT>() {
        c.def(py::init([](typename GridT::Ptr g) {
                  return P(std::in_place_type<GridT>, requireGrid(g, "grid"));
              }),
              py::arg("grid"));
    });
}

void bindLevelSetFilter(py::module_& t) {
    using P = PyLevelSetFilter;
    py::class_<P> c(t, "LevelSetFilter",
                    "LevelSetFilter(grid): smoothing and offsetting of a narrow-band level set "
                    "(FloatGrid or DoubleGrid) in place; every operation rebuilds the band with "
                    "the level set tracker, so the result is again a narrow band of the same "
                    "width. An optional mask (a FloatGrid) blends old and new values as "
                    "(1 - alpha) old + alpha new, alpha being the mask value mapped from "
                    "[minMask, maxMask] to [0, 1]. Raises ValueError for a grid without cubic "
                    "voxels or with a background that is not positive.");
    defGridConstructors<P, RealGridTypes>(c);
    c.def_property_readonly("grid", &P::grid, "the filtered grid");
    c.def(
        "mean",
        [](P& f, int width, const FloatGrid* mask) {
            f.run(mask, "LevelSetFilter.mean", [&](auto& flt) { flt.mean(width, mask); });
        },
        py::arg("width") = 1, py::arg("mask") = nullptr,
        "mean(width=1, mask=None): a box filter of edge 2 width + 1, then a rebuild of the band. "
        "Raises ValueError unless 1 <= width <= 128.");
    c.def(
        "gaussian",
        [](P& f, int width, const FloatGrid* mask) {
            f.run(mask, "LevelSetFilter.gaussian", [&](auto& flt) { flt.gaussian(width, mask); });
        },
        py::arg("width") = 1, py::arg("mask") = nullptr,
        "gaussian(width=1, mask=None): four box filters of edge 2 width + 1 (an approximate "
        "Gaussian), each followed by a rebuild. Raises ValueError unless 1 <= width <= 128.");
    c.def(
        "median",
        [](P& f, int width, const FloatGrid* mask) {
            f.run(mask, "LevelSetFilter.median", [&](auto& flt) { flt.median(width, mask); });
        },
        py::arg("width") = 1, py::arg("mask") = nullptr,
        "median(width=1, mask=None): the median of the (2 width + 1)^3 box, then a rebuild. "
        "Raises ValueError unless 1 <= width <= 16.");
    c.def(
        "meanCurvature",
        [](P& f, const FloatGrid* mask) {
            f.run(mask, "LevelSetFilter.meanCurvature",
                  [&](auto& flt) { flt.meanCurvature(mask); });
        },
        py::arg("mask") = nullptr,
        "meanCurvature(mask=None): one explicit step of mean-curvature flow (time step dx^2/3), "
        "then a rebuild.");
    c.def(
        "laplacian",
        [](P& f, const FloatGrid* mask) {
            f.run(mask, "LevelSetFilter.laplacian", [&](auto& flt) { flt.laplacian(mask); });
        },
        py::arg("mask") = nullptr,
        "laplacian(mask=None): one explicit step of the heat equation (time step dx^2/6), then "
        "a rebuild.");
    c.def(
        "offset",
        [](P& f, double amount, const FloatGrid* mask) {
            f.run(mask, "LevelSetFilter.offset", [&](auto& flt) {
                flt.offset(typename std::decay_t<decltype(flt)>::ValueType(amount), mask);
            });
        },
        py::arg("amount"), py::arg("mask") = nullptr,
        "offset(amount, mask=None): move the surface by `amount` world units along its normal, "
        "inwards for a positive amount (erosion), outwards for a negative one (dilation), in "
        "steps of at most half a voxel. Raises ValueError for a non-finite amount.");
    c.def(
        "normalize",
        [](P& f) {
            f.run(nullptr, "LevelSetFilter.normalize", [](auto& flt) { flt.normalize(); });
        },
        "normalize(): getNormCount() pseudo-time steps of the reinitialisation equation on the "
        "active voxels (restores |grad phi| = 1).");
    c.def(
        "track",
        [](P& f) { f.run(nullptr, "LevelSetFilter.track", [](auto& flt) { flt.track(); }); },
        "track(): rebuild the narrow band (dilate, normalize, trim to the half width, prune).");
    c.def(
        "setMaskRange",
        [](P& f, float min, float max) {
            if (!(min < max))
                throw py::value_error("setMaskRange: expected min < max");
            f.settings().minMask = min;
            f.settings().maxMask = max;
        },
        py::arg("min"), py::arg("max"),
        "setMaskRange(min, max): the mask values mapped to alpha 0 and 1 (default 0 and 1). "
        "Raises ValueError unless min < max.");
    c.def(
        "minMask", [](P& f) { return f.settings().minMask; },
        "minMask() -> float: the mask value mapped to alpha 0.");
    c.def(
        "maxMask", [](P& f) { return f.settings().maxMask; },
        "maxMask() -> float: the mask value mapped to alpha 1.");
    c.def(
        "invertMask", [](P& f, bool invert) { f.settings().invert = invert; },
        py::arg("invert") = true,
        "invertMask(invert=True): map the mask range to alpha 1 to 0 instead of 0 to 1.");
    c.def(
        "isMaskInverted", [](P& f) { return f.settings().invert; }, "isMaskInverted() -> bool");
    c.def(
        "setSpatialScheme",
        [](P& f, math::BiasedGradientScheme s) {
            tools::detail::checkSupported(s);  // the tracker's check: ValueError otherwise
            f.settings().spatial = s;
        },
        py::arg("scheme"),
        "setSpatialScheme(scheme): the upwind scheme of the renormalisation (FIRST_BIAS, "
        "SECOND_BIAS, THIRD_BIAS or HJWENO5_BIAS, the default); WENO5_BIAS, which the library "
        "does not compute, raises ValueError.");
    c.def(
        "getSpatialScheme", [](P& f) { return f.settings().spatial; },
        "getSpatialScheme() -> BiasedGradientScheme");
    c.def(
        "setTemporalScheme",
        [](P& f, math::TemporalIntegrationScheme s) {
            tools::detail::checkSupported(s);
            f.settings().temporal = s;
        },
        py::arg("scheme"),
        "setTemporalScheme(scheme): the Runge-Kutta scheme of the renormalisation (TVD_RK1, the "
        "default, TVD_RK2 or TVD_RK3).");
    c.def(
        "getTemporalScheme", [](P& f) { return f.settings().temporal; },
        "getTemporalScheme() -> TemporalIntegrationScheme");
    c.def(
        "setNormCount",
        [](P& f, int n) {
            if (n < 0)
                throw py::value_error("setNormCount: the count must not be negative");
            f.settings().normCount = n;
        },
        py::arg("count"),
        "setNormCount(count): pseudo-time steps per renormalisation (default 3).");
    c.def(
        "getNormCount", [](P& f) { return f.settings().normCount; }, "getNormCount() -> int");
}

// ---- Filter

/// The grid types of the value filters of Filter.h.
using FilteredGridTypes = RealGridTypes::Append<Vec3SGrid>;

template <typename GridT>
struct FilterOf {
    typename GridT::Ptr grid;
    std::shared_ptr<tools::Filter<GridT, FloatGrid>> filter;
};

class PyFilter {
public:
    template <typename GridT>
    PyFilter(std::in_place_type_t<GridT>, typename GridT::Ptr grid)
        : mImpl(FilterOf<GridT>{grid, std::make_shared<tools::Filter<GridT, FloatGrid>>(*grid)}) {}

    /// Runs `fn(filter, grid)` without the GIL, after the checks of an operation named `op`.
    template <typename FnT>
    void run(const FloatGrid* mask, const char* op, const FnT& fn) {
        std::visit(
            [&](auto& impl) {
                checkUnpinned(&impl.grid->tree(), op);
                checkMaskTree(*impl.grid, mask, op);
                fn(*impl.filter, *impl.grid);
            },
            mImpl);
    }
    /// Calls `fn(filter)` (settings, with the GIL).
    template <typename FnT>
    auto with(const FnT& fn) {
        return std::visit([&](auto& impl) { return fn(*impl.filter); }, mImpl);
    }
    GridBase::Ptr grid() const {
        return std::visit([](const auto& impl) { return GridBase::Ptr(impl.grid); }, mImpl);
    }

private:
    std::variant<FilterOf<FloatGrid>, FilterOf<DoubleGrid>, FilterOf<Vec3SGrid>> mImpl;
};

void checkIterations(int iterations, const char* op) {
    if (iterations < 0)
        throw py::value_error(std::string(op) + ": iterations must not be negative");
}

void bindFilter(py::module_& t) {
    using P = PyFilter;
    py::class_<P> c(t, "Filter",
                    "Filter(grid): smoothing of the active values of a FloatGrid, DoubleGrid or "
                    "Vec3SGrid in place (mean, gaussian, median, offset); active tiles are left as "
                    "they are. An optional mask (a FloatGrid) blends old and new values as "
                    "(1 - alpha) old + alpha new, alpha being the mask value mapped from "
                    "[minMask, maxMask] to [0, 1].");
    defGridConstructors<P, FilteredGridTypes>(c);
    c.def_property_readonly("grid", &P::grid, "the filtered grid");
    c.def(
        "mean",
        [](P& f, int width, int iterations, const FloatGrid* mask) {
            checkIterations(iterations, "Filter.mean");
            f.run(mask, "Filter.mean", [&](auto& flt, auto&) {
                py::gil_scoped_release release;
                flt.mean(width, iterations, mask);
            });
        },
        py::arg("width") = 1, py::arg("iterations") = 1, py::arg("mask") = nullptr,
        "mean(width=1, iterations=1, mask=None): `iterations` box filters of edge 2 width + 1. "
        "Raises ValueError unless 1 <= width <= 128, or for negative iterations.");
    c.def(
        "gaussian",
        [](P& f, int width, int iterations, const FloatGrid* mask) {
            checkIterations(iterations, "Filter.gaussian");
            f.run(mask, "Filter.gaussian", [&](auto& flt, auto&) {
                py::gil_scoped_release release;
                flt.gaussian(width, iterations, mask);
            });
        },
        py::arg("width") = 1, py::arg("iterations") = 1, py::arg("mask") = nullptr,
        "gaussian(width=1, iterations=1, mask=None): `iterations` approximate Gaussian filters, "
        "each four box filters of edge 2 width + 1. Raises ValueError unless 1 <= width <= 128, "
        "or for negative iterations.");
    c.def(
        "median",
        [](P& f, int width, int iterations, const FloatGrid* mask) {
            checkIterations(iterations, "Filter.median");
            f.run(mask, "Filter.median", [&](auto& flt, auto&) {
                py::gil_scoped_release release;
                flt.median(width, iterations, mask);
            });
        },
        py::arg("width") = 1, py::arg("iterations") = 1, py::arg("mask") = nullptr,
        "median(width=1, iterations=1, mask=None): `iterations` median filters over boxes of "
        "edge 2 width + 1. Raises ValueError unless 1 <= width <= 16, or for negative "
        "iterations; TypeError for a Vec3SGrid (vectors have no median).");
    c.def(
        "offset",
        [](P& f, py::handle value, const FloatGrid* mask) {
            f.run(mask, "Filter.offset", [&](auto& flt, auto& grid) {
                using ValueT = typename std::decay_t<decltype(grid)>::ValueType;
                const ValueT v = toValue<ValueT>(value, "Filter.offset");
                py::gil_scoped_release release;
                flt.offset(v, mask);
            });
        },
        py::arg("value"), py::arg("mask") = nullptr,
        "offset(value, mask=None): add `value` to every active voxel. Raises ValueError for a "
        "non-finite value.");
    c.def(
        "setMaskRange",
        [](P& f, float min, float max) { f.with([&](auto& flt) { flt.setMaskRange(min, max); }); },
        py::arg("min"), py::arg("max"),
        "setMaskRange(min, max): the mask values mapped to alpha 0 and 1 (default 0 and 1). "
        "Raises ValueError unless min < max.");
    c.def(
        "minMask", [](P& f) { return f.with([](auto& flt) { return float(flt.minMask()); }); },
        "minMask() -> float: the mask value mapped to alpha 0.");
    c.def(
        "maxMask", [](P& f) { return f.with([](auto& flt) { return float(flt.maxMask()); }); },
        "maxMask() -> float: the mask value mapped to alpha 1.");
    c.def(
        "invertMask", [](P& f, bool invert) { f.with([&](auto& flt) { flt.invertMask(invert); }); },
        py::arg("invert") = true,
        "invertMask(invert=True): map the mask range to alpha 1 to 0 instead of 0 to 1.");
    c.def(
        "isMaskInverted",
        [](P& f) { return f.with([](auto& flt) { return flt.isMaskInverted(); }); },
        "isMaskInverted() -> bool");
    c.def(
        "setGrainSize",
        [](P& f, int grain) { f.with([&](auto& flt) { flt.setGrainSize(grain); }); },
        py::arg("grainSize"),
        "setGrainSize(grainSize): leaves per task; 0 runs serially (the results are the same).");
    c.def(
        "getGrainSize", [](P& f) { return f.with([](auto& flt) { return flt.getGrainSize(); }); },
        "getGrainSize() -> int");
}

// ---- Grid operators

/// The masked form of an operator is instantiated for the float grids only (GridOperators.h).
[[noreturn]] void noMask(const char* op, const char* type) {
    throw py::type_error(std::string(op) + ": a mask is supported for " + type +
                         " inputs only; pass mask=None");
}

template <typename InT, typename PlainT, typename MaskedT>
void defOperator(py::module_& t, const char* name, PlainT plain, MaskedT masked,
                 const char* maskedType, const char* doc) {
    t.def(
        name,
        [plain, masked, name, maskedType](const InT& grid, py::object mask) -> GridBase::Ptr {
            if (mask.is_none()) {
                py::gil_scoped_release release;
                return plain(grid);
            }
            if constexpr (std::is_same_v<MaskedT, std::nullptr_t>) {
                noMask(name, maskedType);
            } else {
                const MaskGrid::ConstPtr m = activeMask(mask, name);
                py::gil_scoped_release release;
                return masked(grid, *m);
            }
        },
        py::arg("grid"), py::arg("mask") = py::none(), doc);
}

/// Binds operator `fn` (tools::gradient, ...) for InT with a mask and for InT2 without.
#define VDB_PY_OPERATOR(t, fn, InT, InT2, doc)                                                \
    defOperator<InT>(                                                                         \
        t, #fn, [](const InT& g) { return GridBase::Ptr(tools::fn(g)); },                     \
        [](const InT& g, const MaskGrid& m) { return GridBase::Ptr(tools::fn(g, m)); }, #InT, \
        doc);                                                                                 \
    defOperator<InT2>(                                                                        \
        t, #fn, [](const InT2& g) { return GridBase::Ptr(tools::fn(g)); }, nullptr, #InT, doc)

void bindOperators(py::module_& t) {
    const char* gradDoc =
        "gradient(grid, mask=None) -> vector grid: the gradient of a FloatGrid (Vec3SGrid) or "
        "DoubleGrid (Vec3DGrid) in world units (second-order central differences), on the "
        "active voxels (those also active in `mask`, any grid, FloatGrid inputs only). Marked "
        "VEC_COVARIANT.";
    VDB_PY_OPERATOR(t, gradient, FloatGrid, DoubleGrid, gradDoc);
    const char* lapDoc =
        "laplacian(grid, mask=None) -> grid: the Laplacian of a FloatGrid or DoubleGrid in "
        "world units, on the active voxels (mask: FloatGrid inputs only).";
    VDB_PY_OPERATOR(t, laplacian, FloatGrid, DoubleGrid, lapDoc);
    const char* curvDoc =
        "meanCurvature(grid, mask=None) -> grid: the mean curvature div(grad phi / |grad phi|) "
        "/ 2 of the level sets of a FloatGrid or DoubleGrid in world units (1/R near a sphere "
        "of radius R), 0 where the gradient vanishes (mask: FloatGrid inputs only).";
    VDB_PY_OPERATOR(t, meanCurvature, FloatGrid, DoubleGrid, curvDoc);
    const char* divDoc =
        "divergence(grid, mask=None) -> grid: the divergence of a Vec3SGrid (FloatGrid) or "
        "Vec3DGrid (DoubleGrid) in world units (forward differences for a STAGGERED grid) "
        "(mask: Vec3SGrid inputs only).";
    VDB_PY_OPERATOR(t, divergence, Vec3SGrid, Vec3DGrid, divDoc);
    const char* curlDoc =
        "curl(grid, mask=None) -> grid: the curl of a Vec3SGrid or Vec3DGrid in world units "
        "(mask: Vec3SGrid inputs only).";
    VDB_PY_OPERATOR(t, curl, Vec3SGrid, Vec3DGrid, curlDoc);
    const char* magDoc =
        "magnitude(grid, mask=None) -> grid: the length of every vector of a Vec3SGrid "
        "(FloatGrid) or Vec3DGrid (DoubleGrid) (mask: Vec3SGrid inputs only).";
    VDB_PY_OPERATOR(t, magnitude, Vec3SGrid, Vec3DGrid, magDoc);
    const char* normDoc =
        "normalize(grid, mask=None) -> grid: every vector of a Vec3SGrid or Vec3DGrid scaled to "
        "unit length (zero vectors stay zero) (mask: Vec3SGrid inputs only).";
    VDB_PY_OPERATOR(t, normalize, Vec3SGrid, Vec3DGrid, normDoc);
}

// ---- Level set measures

template <typename GridT>
struct MeasureOf {
    typename GridT::Ptr grid;
    std::shared_ptr<tools::LevelSetMeasure<GridT>> measure;
};

class PyLevelSetMeasure {
public:
    template <typename GridT>
    PyLevelSetMeasure(std::in_place_type_t<GridT>, typename GridT::Ptr grid) {
        init<GridT>(grid);
    }
    template <typename GridT>
    void init(typename GridT::Ptr grid) {
        py::gil_scoped_release release;
        mImpl = MeasureOf<GridT>{grid, std::make_shared<tools::LevelSetMeasure<GridT>>(*grid)};
    }
    /// Calls `fn(measure)` without the GIL.
    template <typename FnT>
    auto run(const FnT& fn) {
        return std::visit(
            [&](auto& impl) {
                py::gil_scoped_release release;
                return fn(*impl.measure);
            },
            mImpl);
    }
    GridBase::Ptr grid() const {
        return std::visit([](const auto& impl) { return GridBase::Ptr(impl.grid); }, mImpl);
    }

private:
    std::variant<MeasureOf<FloatGrid>, MeasureOf<DoubleGrid>> mImpl;
};

template <typename GridT>
void bindMeasureFunctions(py::module_& t) {
    t.def(
        "levelSetArea",
        [](const GridT& g, bool useWorldSpace) {
            py::gil_scoped_release release;
            return tools::levelSetArea(g, useWorldSpace);
        },
        py::arg("grid"), py::arg("useWorldSpace") = true,
        "levelSetArea(grid, useWorldSpace=True) -> float: the surface area of a narrow-band "
        "level set (FloatGrid or DoubleGrid), in world units (voxel units when useWorldSpace "
        "is False). Raises ValueError for a grid that is not a level set, is empty or has "
        "non-cubic voxels.");
    t.def(
        "levelSetVolume",
        [](const GridT& g, bool useWorldSpace) {
            py::gil_scoped_release release;
            return tools::levelSetVolume(g, useWorldSpace);
        },
        py::arg("grid"), py::arg("useWorldSpace") = true,
        "levelSetVolume(grid, useWorldSpace=True) -> float: the volume enclosed by a "
        "narrow-band level set (errors as levelSetArea).");
    t.def(
        "levelSetEulerCharacteristic",
        [](const GridT& g) {
            py::gil_scoped_release release;
            return tools::levelSetEulerCharacteristic(g);
        },
        py::arg("grid"),
        "levelSetEulerCharacteristic(grid) -> int: the Euler characteristic of the surface (2 "
        "for a sphere, 0 for a torus; summed over connected surfaces).");
    t.def(
        "levelSetGenus",
        [](const GridT& g) {
            py::gil_scoped_release release;
            return tools::levelSetGenus(g);
        },
        py::arg("grid"),
        "levelSetGenus(grid) -> int: the genus of the surface (0 for a sphere, 1 for a torus), "
        "meaningful for one connected surface.");
}

void bindLevelSetMeasure(py::module_& t) {
    RealGridTypes::forEach([&]<typename GridT>() { bindMeasureFunctions<GridT>(t); });
    using P = PyLevelSetMeasure;
    py::class_<P> c(t, "LevelSetMeasure",
                    "LevelSetMeasure(grid): area, volume and curvatures of a narrow-band level "
                    "set (FloatGrid or DoubleGrid), each computed on first request and kept; "
                    "call init(grid) after the grid changes. Raises ValueError for a grid that "
                    "is not a level set, is empty or has non-cubic voxels.");
    defGridConstructors<P, RealGridTypes>(c);
    c.def_property_readonly("grid", &P::grid, "the measured grid");
    c.def(
        "init", [](P& m, FloatGrid::Ptr g) { m.init<FloatGrid>(requireGrid(g, "init")); },
        py::arg("grid"), "init(grid): measure `grid` from now on, forgetting earlier results.");
    c.def(
        "init", [](P& m, DoubleGrid::Ptr g) { m.init<DoubleGrid>(requireGrid(g, "init")); },
        py::arg("grid"));
    c.def(
        "area", [](P& m, bool w) { return m.run([w](auto& s) { return s.area(w); }); },
        py::arg("useWorldUnits") = true,
        "area(useWorldUnits=True) -> float: the surface area (world units, else voxel units).");
    c.def(
        "volume", [](P& m, bool w) { return m.run([w](auto& s) { return s.volume(w); }); },
        py::arg("useWorldUnits") = true,
        "volume(useWorldUnits=True) -> float: the enclosed volume.");
    c.def(
        "totMeanCurvature",
        [](P& m, bool w) { return m.run([w](auto& s) { return s.totMeanCurvature(w); }); },
        py::arg("useWorldUnits") = true,
        "totMeanCurvature(useWorldUnits=True) -> float: the integral of the mean curvature over "
        "the surface (4 pi r on a sphere).");
    c.def(
        "totGaussianCurvature",
        [](P& m, bool w) { return m.run([w](auto& s) { return s.totGaussianCurvature(w); }); },
        py::arg("useWorldUnits") = true,
        "totGaussianCurvature(useWorldUnits=True) -> float: the integral of the Gaussian "
        "curvature over the surface (4 pi on a sphere).");
    c.def(
        "avgMeanCurvature",
        [](P& m, bool w) { return m.run([w](auto& s) { return s.avgMeanCurvature(w); }); },
        py::arg("useWorldUnits") = true,
        "avgMeanCurvature(useWorldUnits=True) -> float: totMeanCurvature() / area() (1/r on a "
        "sphere).");
    c.def(
        "avgGaussianCurvature",
        [](P& m, bool w) { return m.run([w](auto& s) { return s.avgGaussianCurvature(w); }); },
        py::arg("useWorldUnits") = true,
        "avgGaussianCurvature(useWorldUnits=True) -> float: totGaussianCurvature() / area() "
        "(1/r^2 on a sphere).");
    c.def(
        "eulerCharacteristic",
        [](P& m) { return m.run([](auto& s) { return s.eulerCharacteristic(); }); },
        "eulerCharacteristic() -> int: the total Gaussian curvature over 2 pi, rounded.");
    c.def(
        "genus", [](P& m) { return m.run([](auto& s) { return s.genus(); }); },
        "genus() -> int: 1 - eulerCharacteristic() / 2.");
}

#undef VDB_PY_OPERATOR

}  // namespace

void bindToolsFilter(py::module_& t) {
    py::enum_<math::BiasedGradientScheme>(t, "BiasedGradientScheme",
                                          "The upwind schemes of level set renormalisation.")
        .value("FIRST_BIAS", math::FIRST_BIAS)
        .value("SECOND_BIAS", math::SECOND_BIAS)
        .value("THIRD_BIAS", math::THIRD_BIAS)
        .value("WENO5_BIAS", math::WENO5_BIAS)
        .value("HJWENO5_BIAS", math::HJWENO5_BIAS)
        .export_values();
    py::enum_<math::TemporalIntegrationScheme>(t, "TemporalIntegrationScheme",
                                               "The TVD Runge-Kutta schemes of level set tools.")
        .value("TVD_RK1", math::TVD_RK1)
        .value("TVD_RK2", math::TVD_RK2)
        .value("TVD_RK3", math::TVD_RK3)
        .export_values();
    bindLevelSetFilter(t);
    bindFilter(t);
    bindOperators(t);
    bindLevelSetMeasure(t);
}

}  // namespace vdb::python
