// SPDX-License-Identifier: Apache-2.0
// vdb.tools: resampling (resampleToMatch, transformGrid, GridTransformer), point sampling
// (GridSampler), statistics (statistics, extrema, histogram, minMax) and background changes,
// with OpenVDB's names, for the grid types the C++ library instantiates them for.

#include <vdb/Exceptions.h>
#include <vdb/GridTypes.h>
#include <vdb/tools/ChangeBackground.h>
#include <vdb/tools/Count.h>
#include <vdb/tools/GridTransformer.h>
#include <vdb/tools/Interpolation.h>
#include <vdb/tools/Statistics.h>
#include <vdb/tree/ValueAccessor.h>

#include "Common.h"
#include "TreeBlocks.h"

#include <string>
#include <variant>

namespace vdb::python {

namespace {

// ---- Samplers

enum class SamplerKind { Point, Box, Quadratic };

SamplerKind samplerFromPython(const std::string& name, const char* op) {
    if (name == "point")
        return SamplerKind::Point;
    if (name == "box")
        return SamplerKind::Box;
    if (name == "quadratic")
        return SamplerKind::Quadratic;
    throw py::value_error(std::string(op) + ": unknown sampler \"" + name +
                          "\" (expected \"point\", \"box\" or \"quadratic\")");
}

/// Calls `fn.template operator()<SamplerT>()` for the sampler `kind`.
template <typename FnT>
auto withSampler(SamplerKind kind, const FnT& fn) {
    switch (kind) {
        case SamplerKind::Point:
            return fn.template operator()<tools::PointSampler>();
        case SamplerKind::Box:
            return fn.template operator()<tools::BoxSampler>();
        default:
            return fn.template operator()<tools::QuadraticSampler>();
    }
}

const char* const SAMPLER_DOC =
    "sampler: \"point\" (nearest voxel), \"box\" (trilinear, the default) or \"quadratic\" "
    "(triquadratic).";

// ---- Resampling

/// The grid types resampleToMatch and transformGrid take.
using ResampledGridTypes = RealGridTypes::Append<Vec3SGrid>;

template <typename GridT>
void bindResample(py::module_& t) {
    t.def(
        "resampleToMatch",
        [](const GridT& in, GridT& out, const std::string& sampler) {
            const SamplerKind kind = samplerFromPython(sampler, "resampleToMatch");
            checkUnpinned(&out.tree(), "resampleToMatch");
            py::gil_scoped_release release;
            withSampler(kind,
                        [&]<typename SamplerT>() { tools::resampleToMatch<SamplerT>(in, out); });
        },
        py::arg("inGrid"), py::arg("outGrid"), py::arg("sampler") = "box",
        (std::string(
             "resampleToMatch(inGrid, outGrid, sampler=\"box\"): resample inGrid into the index "
             "space of outGrid (FloatGrid, DoubleGrid or Vec3SGrid, both of one type); outGrid "
             "keeps its transform and metadata and gets a new tree. A level set is rebuilt into a "
             "clean narrow band in outGrid's index space (with unequal scales, index-space "
             "distances times the first voxel size, as in OpenVDB); equal transforms or "
             "whole-voxel translations copy the values exactly. Raises ValueError for frustum "
             "transforms or an output of more than 2^34 voxels. ") +
         SAMPLER_DOC)
            .c_str());
    t.def(
        "transformGrid",
        [](const GridT& in, GridT& out, py::handle matrix, const std::string& sampler) {
            const math::Mat4d m = matrixFromPython(matrix);
            const SamplerKind kind = samplerFromPython(sampler, "transformGrid");
            checkUnpinned(&out.tree(), "transformGrid");
            py::gil_scoped_release release;
            const tools::GridTransformer xform(m);
            withSampler(kind, [&]<typename SamplerT>() { xform.transformGrid<SamplerT>(in, out); });
        },
        py::arg("inGrid"), py::arg("outGrid"), py::arg("matrix"), py::arg("sampler") = "box",
        (std::string("transformGrid(inGrid, outGrid, matrix, sampler=\"box\"): replace the tree "
                     "of outGrid by inGrid's voxels mapped by the 4 x 4 index-space matrix "
                     "(row vectors: the voxel at p goes to p * matrix), resampled; outGrid keeps "
                     "its transform and metadata. Raises ValueError for a matrix that is not "
                     "affine, finite and invertible. ") +
         SAMPLER_DOC)
            .c_str());
}

py::list matrixToPython(const math::Mat4d& m) {
    py::list rows;
    for (int r = 0; r < 4; ++r)
        rows.append(py::make_tuple(m(r, 0), m(r, 1), m(r, 2), m(r, 3)));
    return rows;
}

template <typename GridT>
void bindTransformerMethod(py::class_<tools::GridTransformer>& c) {
    c.def(
        "transformGrid",
        [](const tools::GridTransformer& x, const GridT& in, GridT& out,
           const std::string& sampler) {
            const SamplerKind kind = samplerFromPython(sampler, "GridTransformer.transformGrid");
            checkUnpinned(&out.tree(), "GridTransformer.transformGrid");
            py::gil_scoped_release release;
            withSampler(kind, [&]<typename SamplerT>() { x.transformGrid<SamplerT>(in, out); });
        },
        py::arg("inGrid"), py::arg("outGrid"), py::arg("sampler") = "box",
        "transformGrid(inGrid, outGrid, sampler=\"box\"): replace the tree of outGrid by inGrid "
        "(FloatGrid, DoubleGrid or Vec3SGrid) resampled under getTransform(); outGrid keeps its "
        "transform and metadata; a level set is resampled over its band and flood-filled.");
}

void bindGridTransformer(py::module_& t) {
    using X = tools::GridTransformer;
    py::class_<X> c(t, "GridTransformer",
                    "GridTransformer(matrix) or GridTransformer(pivot, scale, rotate, translate, "
                    "xformOrder=\"tsr\", rotOrder=\"zyx\"): a linear map of index space applied "
                    "to grids; the voxel at index point p of the input goes to p * matrix (row "
                    "vectors) in the output. Rotations are Euler angles in radians about the "
                    "pivot. Raises ValueError for a singular, non-affine or non-finite map or "
                    "an order string that is not a permutation of \"tsr\" or \"xyz\".");
    c.def(py::init([](py::handle matrix) { return X(matrixFromPython(matrix)); }),
          py::arg("matrix"));
    c.def(py::init<const Vec3R&, const Vec3R&, const Vec3R&, const Vec3R&, const std::string&,
                   const std::string&>(),
          py::arg("pivot"), py::arg("scale"), py::arg("rotate"), py::arg("translate"),
          py::arg("xformOrder") = "tsr", py::arg("rotOrder") = "zyx");
    c.def(
        "getTransform", [](const X& x) { return matrixToPython(x.getTransform()); },
        "getTransform() -> list of 4 rows: the map from input to output index space.");
    c.def("getMipLevels", &X::getMipLevels,
          "getMipLevels() -> (x, y, z): the halvings applied along each axis before the rest of "
          "the map (mipmapping samplers).");
    c.def("setThreaded", &X::setThreaded, py::arg("threaded"),
          "setThreaded(threaded): run in parallel over output leaves (the default) or serially.");
    c.def("threaded", &X::threaded, "threaded() -> bool");
    ResampledGridTypes::forEach([&]<typename GridT>() { bindTransformerMethod<GridT>(c); });
}

// ---- GridSampler

template <typename GridT>
struct SamplerOf {
    typename GridT::Ptr grid;
};

/// A grid and a sampler kind; reads through a fresh accessor per call.
class PyGridSampler {
public:
    template <typename GridT>
    PyGridSampler(std::in_place_type_t<GridT>, typename GridT::Ptr grid, SamplerKind kind)
        : mImpl(SamplerOf<GridT>{grid}), mKind(kind) {}

    /// One point, index space unless `world`.
    py::object one(const Vec3d& p, bool world) const {
        return std::visit(
            [&](const auto& impl) -> py::object {
                const auto& grid = *impl.grid;
                const auto acc = grid.getConstAccessor();
                const Vec3d ijk = world ? grid.transform().worldToIndex(p) : p;
                return py::cast(withSampler(
                    mKind, [&]<typename SamplerT>() { return SamplerT::sample(acc, ijk); }));
            },
            mImpl);
    }

    /// A point, or an (N, 3) NumPy array of points to an array of N values (N x 3 for
    /// vectors).
    py::object sample(py::handle obj, bool world) const {
        if (!py::isinstance<py::array>(obj) || py::reinterpret_borrow<py::array>(obj).ndim() != 2)
            return one(toValue<Vec3d>(obj, "GridSampler"), world);
        auto points = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(obj);
        if (!points || points.shape(1) != 3)
            throw py::type_error(
                "GridSampler: expected a point (x, y, z) or an array of shape "
                "(N, 3)");
        return std::visit(
            [&](const auto& impl) -> py::object {
                using GridT = typename std::decay_t<decltype(*impl.grid)>;
                using ValueT = typename GridT::ValueType;
                using Scalar = typename ValueTraits<ValueT>::Scalar;
                constexpr int N = ValueTraits<ValueT>::N;
                const py::ssize_t n = points.shape(0);
                py::array_t<Scalar> out =
                    N == 1 ? py::array_t<Scalar>({n}) : py::array_t<Scalar>({n, py::ssize_t(N)});
                const double* src = points.data();
                ValueT* dst = reinterpret_cast<ValueT*>(out.mutable_data());
                const GridT& grid = *impl.grid;
                py::gil_scoped_release release;
                const auto acc = grid.getConstAccessor();
                withSampler(mKind, [&]<typename SamplerT>() {
                    for (py::ssize_t i = 0; i < n; ++i) {
                        const Vec3d p(src[3 * i], src[3 * i + 1], src[3 * i + 2]);
                        dst[i] =
                            SamplerT::sample(acc, world ? grid.transform().worldToIndex(p) : p);
                    }
                    return 0;
                });
                return out;
            },
            mImpl);
    }

    GridBase::Ptr grid() const {
        return std::visit([](const auto& impl) { return GridBase::Ptr(impl.grid); }, mImpl);
    }

private:
    std::variant<SamplerOf<FloatGrid>, SamplerOf<DoubleGrid>, SamplerOf<Vec3SGrid>,
                 SamplerOf<Vec3DGrid>>
        mImpl;
    SamplerKind mKind;
};

template <typename GridT>
void bindSamplerInit(py::class_<PyGridSampler>& c) {
    c.def(py::init([](typename GridT::Ptr g, const std::string& sampler) {
              return PyGridSampler(std::in_place_type<GridT>, requireGrid(g, "GridSampler"),
                                   samplerFromPython(sampler, "GridSampler"));
          }),
          py::arg("grid"), py::arg("sampler") = "box");
}

void bindGridSampler(py::module_& t) {
    using P = PyGridSampler;
    py::class_<P> c(t, "GridSampler",
                    (std::string("GridSampler(grid, sampler=\"box\"): reconstructs the values of a "
                                 "FloatGrid, DoubleGrid, Vec3SGrid or Vec3DGrid between voxels "
                                 "(voxel-centred: index point (i, j, k) is voxel (i, j, k)). ") +
                     SAMPLER_DOC)
                        .c_str());
    FloatingPointGridTypes::forEach([&]<typename GridT>() { bindSamplerInit<GridT>(c); });
    c.def_property_readonly("grid", &P::grid, "the sampled grid");
    c.def(
        "isSample", [](const P& s, py::handle ijk) { return s.sample(ijk, false); }, py::arg("ijk"),
        "isSample(ijk) -> value: the reconstruction at an index-space point (x, y, z); a NumPy "
        "array of shape (N, 3) gives an array of N values.");
    c.def(
        "wsSample", [](const P& s, py::handle xyz) { return s.sample(xyz, true); }, py::arg("xyz"),
        "wsSample(xyz) -> value: the reconstruction at a world-space point (x, y, z); a NumPy "
        "array of shape (N, 3) gives an array of N values.");
}

// ---- Statistics

enum class Which { On, Off, All };

Which whichFromPython(const std::string& s, const char* op) {
    if (s == "on")
        return Which::On;
    if (s == "off")
        return Which::Off;
    if (s == "all")
        return Which::All;
    throw py::value_error(std::string(op) + ": values must be \"on\", \"off\" or \"all\", not \"" +
                          s + "\"");
}

/// Calls `fn(iter)` with the value iterator `which` of `grid`.
template <typename GridT, typename FnT>
auto withIterator(const GridT& grid, Which which, const FnT& fn) {
    switch (which) {
        case Which::On:
            return fn(grid.tree().cbeginValueOn());
        case Which::Off:
            return fn(grid.tree().cbeginValueOff());
        default:
            return fn(grid.tree().cbeginValueAll());
    }
}

/// The largest histogram accepted: 2^26 bins (512 MiB of counts per partial result).
constexpr int MAX_HISTOGRAM_BINS = 1 << 26;

template <typename GridT>
void bindStatistics(py::module_& t) {
    t.def(
        "statistics",
        [](const GridT& g, const std::string& values) {
            const Which which = whichFromPython(values, "statistics");
            math::Stats s;
            {
                py::gil_scoped_release release;
                s = withIterator(g, which, [](const auto& it) { return tools::statistics(it); });
            }
            py::dict d;
            d["count"] = s.size();
            d["min"] = s.min();
            d["max"] = s.max();
            d["mean"] = s.mean();
            d["variance"] = s.variance();
            d["stdDev"] = s.stdDev();
            return d;
        },
        py::arg("grid"), py::arg("values") = "on",
        "statistics(grid, values=\"on\") -> dict: count, min, max, mean, variance (population) "
        "and stdDev of the active (\"on\"), inactive (\"off\") or all (\"all\") values of the "
        "grid; a tile counts as many samples as it has voxels; vectors contribute their length.");
    t.def(
        "extrema",
        [](const GridT& g, const std::string& values) {
            const Which which = whichFromPython(values, "extrema");
            math::Extrema e;
            {
                py::gil_scoped_release release;
                e = withIterator(g, which, [](const auto& it) { return tools::extrema(it); });
            }
            py::dict d;
            d["count"] = e.size();
            d["min"] = e.min();
            d["max"] = e.max();
            return d;
        },
        py::arg("grid"), py::arg("values") = "on",
        "extrema(grid, values=\"on\") -> dict: count, min and max of the chosen values (vector "
        "lengths for vector grids).");
    t.def(
        "histogram",
        [](const GridT& g, double min, double max, int numBins, const std::string& values) {
            const Which which = whichFromPython(values, "histogram");
            if (numBins < 1 || numBins > MAX_HISTOGRAM_BINS)
                throw py::value_error("histogram: numBins must be 1 to " +
                                      std::to_string(MAX_HISTOGRAM_BINS) + ", not " +
                                      std::to_string(numBins));
            std::vector<uint64_t> counts;
            {
                py::gil_scoped_release release;
                const math::Histogram h = withIterator(g, which, [&](const auto& it) {
                    return tools::histogram(it, min, max, size_t(numBins));
                });
                counts.resize(h.numBins());
                for (size_t i = 0; i < counts.size(); ++i)
                    counts[i] = h.count(int(i));
            }
            return py::array_t<uint64_t>(py::ssize_t(counts.size()), counts.data());
        },
        py::arg("grid"), py::arg("min"), py::arg("max"), py::arg("numBins") = 10,
        py::arg("values") = "on",
        "histogram(grid, min, max, numBins=10, values=\"on\") -> uint64 array: the counts of "
        "numBins equal bins over [min, max] of the chosen values (values outside are not "
        "counted). Raises ValueError unless min < max (finite) and 1 <= numBins <= 2^26.");
}

template <typename GridT>
void bindMinMax(py::module_& t) {
    using ValueT = typename GridT::ValueType;
    t.def(
        "minMax",
        [](const GridT& g) {
            math::MinMax<ValueT> mm(ValueT{}, ValueT{});
            {
                py::gil_scoped_release release;
                mm = tools::minMax(g.tree());
            }
            return py::make_tuple(mm.min(), mm.max());
        },
        py::arg("grid"),
        "minMax(grid) -> (min, max): the smallest and largest active values, voxels and tiles "
        "(vectors: OpenVDB's componentwise order); both zero without active values.");
}

template <typename GridT>
void bindBackground(py::module_& t) {
    using ValueT = typename GridT::ValueType;
    t.def(
        "changeBackground",
        [](GridT& g, const ValueT& background) {
            checkUnpinned(&g.tree(), "changeBackground");
            py::gil_scoped_release release;
            tools::changeBackground(g.tree(), background);
        },
        py::arg("grid"), py::arg("background"),
        "changeBackground(grid, background): every inactive value equal to the old background "
        "becomes `background` (and every one equal to minus it, -background); active values do "
        "not change.");
    if constexpr (std::is_floating_point_v<ValueT>) {
        t.def(
            "changeLevelSetBackground",
            [](GridT& g, ValueT halfWidth) {
                checkUnpinned(&g.tree(), "changeLevelSetBackground");
                py::gil_scoped_release release;
                tools::changeLevelSetBackground(g.tree(), halfWidth);
            },
            py::arg("grid"), py::arg("halfWidth"),
            "changeLevelSetBackground(grid, halfWidth): every inactive value of the level set "
            "becomes halfWidth where it is not negative and -halfWidth where it is; halfWidth "
            "(world units) becomes the background. Raises ValueError unless halfWidth > 0.");
        t.def(
            "changeAsymmetricLevelSetBackground",
            [](GridT& g, ValueT outsideWidth, ValueT insideWidth) {
                checkUnpinned(&g.tree(), "changeAsymmetricLevelSetBackground");
                py::gil_scoped_release release;
                tools::changeAsymmetricLevelSetBackground(g.tree(), outsideWidth, insideWidth);
            },
            py::arg("grid"), py::arg("outsideWidth"), py::arg("insideWidth"),
            "changeAsymmetricLevelSetBackground(grid, outsideWidth, insideWidth): every inactive "
            "value becomes outsideWidth where it is not negative and insideWidth where it is; "
            "outsideWidth becomes the background. Raises ValueError unless outsideWidth >= 0 "
            "and insideWidth < 0.");
    }
}

}  // namespace

void bindToolsSample(py::module_& t) {
    ResampledGridTypes::forEach([&]<typename GridT>() { bindResample<GridT>(t); });
    bindGridTransformer(t);
    bindGridSampler(t);
    NumericGridTypes::Append<Vec3SGrid, Vec3DGrid>::forEach(
        [&]<typename GridT>() { bindStatistics<GridT>(t); });
    GridTypes::Remove<MaskGrid>::forEach([&]<typename GridT>() { bindMinMax<GridT>(t); });
    GridTypes::Remove<BoolGrid, MaskGrid>::forEach(
        [&]<typename GridT>() { bindBackground<GridT>(t); });
}

}  // namespace vdb::python
