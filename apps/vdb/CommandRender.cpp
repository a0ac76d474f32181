// SPDX-License-Identifier: Apache-2.0
/// @file
/// `vdb render IN.vdb -o OUT.png`: a picture of a level set (ray-traced surface) or of a fog
/// volume (single scattering from a sun with shadows, plus an ambient sky), framed
/// automatically or by camera options, written as PNG or EXR with the opacity as alpha. A '#'
/// in the input's file name renders a frame sequence with one camera.

#include <vdb/render/Camera.h>
#include <vdb/render/Renderer.h>

#include "Commands.h"
#include "ImageFiles.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

namespace vdb::app {
namespace {

namespace fs = std::filesystem;

struct RenderArgs {
    std::string input;
    std::string output;
    std::string grid;
    bool gridGiven = false;
    CLI::Option* gridOption = nullptr;
    std::string normals;
    std::string mode = "auto";
    std::string camera = "perspective";
    size_t width = 960;
    size_t height = 720;
    double fov = 40.0;
    std::vector<double> view{-1.0, -0.6, -1.2};
    std::vector<double> up{0.0, 1.0, 0.0};
    std::vector<double> position, lookAt;
    std::vector<double> light;  // empty: from the upper right of the camera
    std::vector<double> background;
    double ambient = -1.0;     // < 0: the mode's default
    double extinction = -1.0;  // < 0: derived from the data
    double step = 0.5;
    double shadowStep = 1.0;
};

// Fog: the optical depth the densest rays of the picture reach by default (the 90th
// percentile of the rays that meet density), and the default lighting.
constexpr double kFogOpticalDepth = 4.0;
constexpr double kFogAmbient = 0.3;
constexpr double kSurfaceAmbient = 0.12;
// The default light, in the camera's frame: right, up, and towards the camera.
constexpr double kLightRight = 0.45, kLightUp = 0.65, kLightBack = 0.6;

Vec3d toVec(const std::vector<double>& v) {
    return Vec3d(v[0], v[1], v[2]);
}

std::string vecText(const std::vector<double>& v) {
    std::string s;
    for (double x : v) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%g", x);
        if (!s.empty())
            s += ',';
        s += buf;
    }
    return s;
}

// ---- Option checks ----------------------------------------------------------------------------

/// Adds a vector option x,y,z whose components must be finite numbers.
CLI::Option* addVector(CLI::App& cmd, const std::string& name, std::vector<double>& v,
                       const std::string& help, bool showDefault) {
    CLI::Option* opt = cmd.add_option(name, v, help)
                           ->expected(3)
                           ->delimiter(',')
                           ->check(finite())
                           ->type_name("X,Y,Z");
    if (showDefault)
        opt->default_str(vecText(v));
    return opt;
}

/// Checks what the per-option checks cannot see: vectors that must not be zero, an up
/// vector along the view, a camera looking at its own position.
void checkVectors(const RenderArgs& a) {
    const auto zero = [](const std::vector<double>& v) {
        return v[0] == 0.0 && v[1] == 0.0 && v[2] == 0.0;
    };
    if (zero(a.view))
        throw UsageError("--view " + vecText(a.view) +
                         ": the view direction must be a non-zero vector");
    if (zero(a.up))
        throw UsageError("--up " + vecText(a.up) + ": the up direction must be a non-zero vector");
    if (!a.light.empty() && zero(a.light))
        throw UsageError("--light " + vecText(a.light) +
                         ": the direction towards the light must be a non-zero vector");
    if (!a.lookAt.empty() && a.position.empty())
        throw UsageError("--look-at needs --position (or use --view for automatic framing)");
    if (!a.position.empty() && a.lookAt.empty())
        throw UsageError("--position needs --look-at");
    Vec3d view = toVec(a.view);
    if (!a.position.empty()) {
        view = toVec(a.lookAt) - toVec(a.position);
        if (!(view.length() > 0.0))
            throw UsageError("--position " + vecText(a.position) + " and --look-at " +
                             vecText(a.lookAt) + " must differ");
    }
    const Vec3d up = toVec(a.up);
    if (!(view.unitSafe(0.0).cross(up.unitSafe(0.0)).length() > 1e-9))
        throw UsageError("--up " + vecText(a.up) + " must not be parallel to the view direction");
}

// ---- Frame sequences --------------------------------------------------------------------------

/// One file of a frame sequence: its number, the digits that name it, and its path.
struct Frame : FrameNumber {
    std::string path;
};

/// The frames matching `pattern`, whose file name holds one run of '#': a single '#' stands
/// for a frame number of any number of digits ("0001", "17"), a run of n for one of at least n
/// digits; sorted by number. Empty when `pattern` names no sequence (no '#' in the file name,
/// or an existing file of that very name).
/// @throw UsageError when no file matches or two files give the same number.
std::vector<Frame> listFrames(const std::string& pattern) {
    std::error_code ec;
    const fs::path folder = fs::path(pattern).parent_path();
    const std::string namePattern = fs::path(pattern).filename().string();
    const auto run = frameHashRun(namePattern, "input " + pattern);
    if (!run || fs::is_regular_file(pattern, ec))
        return {};
    const std::string prefix = namePattern.substr(0, run->first);
    const std::string suffix = namePattern.substr(run->first + run->second);
    std::map<uint64_t, Frame> frames;
    for (const auto& entry : fs::directory_iterator(folder.empty() ? fs::path(".") : folder, ec)) {
        const std::string name = entry.path().filename().string();
        if (name.size() <= prefix.size() + suffix.size() || name.rfind(prefix, 0) != 0 ||
            name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
            continue;
        const std::string digits =
            name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
        if (digits.size() < run->second || digits.size() > 18 ||
            !std::all_of(digits.begin(), digits.end(),
                         [](unsigned char c) { return std::isdigit(c); }))
            continue;
        std::error_code typeError;
        if (!entry.is_regular_file(typeError))
            continue;
        Frame f;
        f.number = std::stoull(digits);
        f.digits = digits;
        f.path = folder.empty() ? name : (folder / name).string();
        const auto [it, inserted] = frames.emplace(f.number, f);
        if (!inserted)
            throw UsageError("input " + pattern + ": " + it->second.path + " and " + f.path +
                             " are both frame " + std::to_string(f.number));
    }
    if (frames.empty())
        throw UsageError("no file matches " + pattern + " (# stands for a frame number)");
    std::vector<Frame> out;
    for (auto& entry : frames)
        out.push_back(std::move(entry.second));
    return out;
}

// ---- Grid choice ------------------------------------------------------------------------------

/// What the choice of a grid needs to know about one grid of a file.
struct GridInfo {
    std::string name;
    size_t index = 0;     // among the grids of the file with this name, in file order
    size_t sameName = 1;  // how many grids of the file have this name
    bool floating = false;
    bool levelSet = false;
    GridClass gridClass = GRID_UNKNOWN;
    std::string type;
    bool empty = true;  // level set: no active voxel; fog: no positive value
    render::FogVolumeStats fog;
    BBoxd worldBox;  // the box to frame: active voxels (level set), positive values (fog)
    GridBase::Ptr grid;
};

/// "density", "density[1]" (when several grids share the name), "[0]" for an unnamed grid.
std::string gridLabel(const std::string& name, size_t index, size_t sameName) {
    if (sameName > 1 || name.empty())
        return name + "[" + std::to_string(index) + "]";
    return name;
}
std::string gridLabel(const GridInfo& g) {
    return gridLabel(g.name, g.index, g.sameName);
}

/// Facts about every grid of `grids`; fog statistics for the floating-point grids that are not
/// level sets (and for level sets too with `fogMode`).
std::vector<GridInfo> describeGrids(const GridPtrVec& grids, bool fogMode, bool threaded) {
    std::vector<GridInfo> infos;
    std::map<std::string, size_t> counts;
    for (const auto& g : grids)
        ++counts[g->getName()];
    std::map<std::string, size_t> seen;
    for (const auto& g : grids) {
        GridInfo info;
        info.grid = g;
        info.name = g->getName();
        info.index = seen[info.name]++;
        info.sameName = counts[info.name];
        info.gridClass = g->getGridClass();
        info.levelSet = info.gridClass == GRID_LEVEL_SET;
        info.type = g->type();
        info.floating = gridIsOneOf<RealGridTypes>(*g);
        if (info.floating) {
            if (info.levelSet && !fogMode) {
                const CoordBBox box = g->evalActiveVoxelBoundingBox();
                info.empty = box.empty();
                if (!info.empty)
                    info.worldBox = g->transform().indexToWorld(box);
            } else {
                withLevelSetGrid(g, [&](const auto& typed) {
                    info.fog = render::evalFogVolumeStats(typed, threaded);
                });
                info.empty = info.fog.empty();
                if (!info.empty)
                    info.worldBox = info.fog.worldBBox(g->transform());
            }
        }
        infos.push_back(std::move(info));
    }
    return infos;
}

/// A --grid value: NAME, or NAME[INDEX] to pick one of several grids named NAME.
struct GridSpec {
    std::string name;
    std::optional<size_t> index;
};

/// Parses `text` against the grids' names: a name that exists as written is taken whole (even
/// with brackets); else a trailing [INDEX] is split off.
GridSpec parseGridSpec(const std::string& text, const std::vector<GridInfo>& infos) {
    for (const GridInfo& g : infos)
        if (g.name == text)
            return {text, std::nullopt};
    if (text.size() >= 3 && text.back() == ']') {
        const size_t open = text.rfind('[');
        const std::string digits =
            open == std::string::npos ? "" : text.substr(open + 1, text.size() - open - 2);
        if (!digits.empty() && digits.size() <= 9 &&
            std::all_of(digits.begin(), digits.end(),
                        [](unsigned char c) { return std::isdigit(c); }))
            return {text.substr(0, open), size_t(std::stoul(digits))};
    }
    return {text, std::nullopt};
}

std::string availableGrids(const std::vector<GridInfo>& infos) {
    std::string names;
    for (const GridInfo& g : infos)
        names += (names.empty() ? "\"" : ", \"") + gridLabel(g) + "\"";
    return names;
}

/// The grid named by `spec` in `infos`, or null. @throw UsageError naming the available grids
/// (with their indices where names repeat) when `required` and there is none.
const GridInfo* findGrid(const std::vector<GridInfo>& infos, const GridSpec& spec,
                         const std::string& path, bool required) {
    for (const GridInfo& g : infos)
        if (g.name == spec.name && g.index == spec.index.value_or(0))
            return &g;
    if (!required)
        return nullptr;
    const std::string wanted =
        spec.name + (spec.index ? "[" + std::to_string(*spec.index) + "]" : "");
    throw UsageError(path + " has no grid " +
                     (wanted.empty() ? "without a name" : "\"" + wanted + "\"") +
                     (infos.empty() ? "" : " (it has " + availableGrids(infos) + ")"));
}

/// The grid to render when none is named: in this order, the first non-empty grid named
/// "density", the first non-empty fog volume, the first non-empty level set, then any other
/// non-empty floating-point grid; only level sets with --mode levelset, and no level set with
/// --mode fog. Grids are non-empty when they are in any of the frames (`nonEmpty`).
/// @throw UsageError when no floating-point grid holds anything.
const GridInfo& chooseGrid(const std::vector<GridInfo>& infos, const std::vector<uint8_t>& nonEmpty,
                           const std::string& mode, const std::string& path) {
    const auto lower = [](std::string s) {
        std::transform(s.begin(), s.end(), s.begin(),
                       [](unsigned char c) { return char(std::tolower(c)); });
        return s;
    };
    const auto rank = [&](const GridInfo& g) -> int {
        if (mode == "levelset")
            return g.levelSet ? 2 : -1;
        if (mode == "fog" && g.levelSet)
            return -1;
        if (lower(g.name) == "density")
            return 0;
        if (g.gridClass == GRID_FOG_VOLUME)
            return 1;
        return g.levelSet ? 2 : 3;
    };
    const GridInfo* best = nullptr;
    int bestRank = 4;
    for (size_t i = 0; i < infos.size(); ++i) {
        const GridInfo& g = infos[i];
        if (!g.floating || !nonEmpty[i])
            continue;
        const int r = rank(g);
        if (r >= 0 && r < bestRank) {
            best = &g;
            bestRank = r;
        }
    }
    if (best)
        return *best;
    std::string kind = "float or double grid", candidates;
    if (mode != "auto")
        kind = mode == "levelset" ? "level set" : "float or double grid that is not a level set";
    for (const GridInfo& g : infos)
        if (g.floating && rank(g) >= 0)
            candidates += (candidates.empty() ? "\"" : ", \"") + gridLabel(g) + "\"";
    if (candidates.empty())
        throw UsageError(path + " has no " + kind + " to render" +
                         (infos.empty() ? "" : " (it has " + availableGrids(infos) + ")"));
    throw UsageError(path + ": every " + kind + " is empty (" + candidates +
                     "): nothing to render");
}

// ---- Camera -----------------------------------------------------------------------------------

std::unique_ptr<render::Camera> makeCamera(const RenderArgs& a, const BBoxd& worldBox) {
    const Vec3d up = toVec(a.up);
    if (!a.position.empty()) {
        if (a.camera == "ortho")
            return std::make_unique<render::OrthographicCamera>(a.width, a.height,
                                                                toVec(a.position), toVec(a.lookAt),
                                                                up, worldBox.extents().length());
        return std::make_unique<render::PerspectiveCamera>(a.width, a.height, toVec(a.position),
                                                           toVec(a.lookAt), up, a.fov);
    }
    if (a.camera == "ortho")
        return std::make_unique<render::OrthographicCamera>(
            render::OrthographicCamera::frame(worldBox, a.width, a.height, toVec(a.view), up));
    return std::make_unique<render::PerspectiveCamera>(
        render::PerspectiveCamera::frame(worldBox, a.width, a.height, toVec(a.view), a.fov, up));
}

// ---- The command ------------------------------------------------------------------------------

/// Bytes the pictures of one frame need: the float image (and the normals), and the encoded
/// copy the writer makes.
double pictureBytes(const RenderArgs& a) {
    const double pixels = double(a.width) * double(a.height);
    const auto encoded = [](const std::string& path) {
        return imageFormatFor(path) == ImageFormat::Exr ? 16.0 : 4.0;
    };
    double bytes = pixels * (double(sizeof(render::Rgba)) + encoded(a.output));
    if (!a.normals.empty())
        bytes += pixels * (double(sizeof(render::Rgba)) + encoded(a.normals));
    return bytes;
}

/// Whether any pixel of `image` shows something other than the background `bg`.
bool covers(const render::Image& image, const render::Rgba& bg) {
    for (size_t y = 0; y < image.height(); ++y)
        for (size_t x = 0; x < image.width(); ++x)
            if (!(image(x, y) == bg))
                return true;
    return false;
}

/// Reruns `f`, naming the frame in the message of what it throws (keeping the exit status:
/// UsageError stays a UsageError).
template <typename F>
void forFrame(const Frame* frame, F&& f) {
    if (!frame)
        return f();
    const std::string where = "frame " + std::to_string(frame->number) + " (" + frame->path + "): ";
    try {
        f();
    } catch (const UsageError& e) {
        throw UsageError(where + e.what());
    } catch (const vdb::Exception& e) {
        throw IoError(where + e.what());
    } catch (const std::bad_alloc&) {
        throw;
    } catch (const std::exception& e) {
        throw std::runtime_error(where + e.what());
    }
}

void runRender(const RenderArgs& a, Context& ctx) {
    // Everything that can be checked without reading: options, outputs, memory.
    checkVectors(a);
    const std::vector<Frame> frames = listFrames(a.input);
    const bool sequence = !frames.empty();
    imageFormatFor(a.output);
    if (!a.normals.empty())
        imageFormatFor(a.normals);
    if (sequence) {
        framePath(a.output, frames.front(), "-o");
        if (!a.normals.empty())
            framePath(a.normals, frames.front(), "--normals");
    }
    const auto outputFor = [&](const std::string& pattern, const Frame* f,
                               const std::string& option) {
        return f ? framePath(pattern, *f, option) : pattern;
    };
    const Frame* firstFrame = sequence ? &frames.front() : nullptr;
    checkOutputPath(outputFor(a.output, firstFrame, "-o"));
    if (!a.normals.empty())
        checkOutputPath(outputFor(a.normals, firstFrame, "--normals"));
    checkMemoryEstimate(pictureBytes(a), "a " + std::to_string(a.width) + "x" +
                                             std::to_string(a.height) + " picture");
    const bool threaded = ctx.threads != 1;
    const bool fogMode = a.mode == "fog";

    Report report(ctx);
    const size_t count = sequence ? frames.size() : 1;
    const auto tag = [&](size_t i) {
        return sequence ? "[" + std::to_string(i + 1) + "/" + std::to_string(count) + "] " : "";
    };
    const auto inputOf = [&](size_t i) { return sequence ? frames[i].path : a.input; };
    const auto frameOf = [&](size_t i) { return sequence ? &frames[i] : nullptr; };

    // Pass 1: the grids of every frame, to choose one grid and one camera for all.
    std::vector<std::vector<GridInfo>> infos(count);
    for (size_t i = 0; i < count; ++i)
        forFrame(frameOf(i), [&] {
            const GridPtrVec grids = report.step(tag(i) + "read " + inputOf(i),
                                                 [&] { return readGrids(inputOf(i), ctx); });
            infos[i] = describeGrids(grids, fogMode, threaded);
            if (sequence)  // kept for the single file only; frames are read again to render
                for (GridInfo& g : infos[i])
                    g.grid.reset();
        });
    const std::string where =
        sequence ? a.input + " (frame " + std::to_string(frames[0].number) + ")" : a.input;
    // The chosen grid, by name and index, in the first frame.
    GridSpec spec;
    const GridInfo* chosen = nullptr;
    if (a.gridGiven) {
        spec = parseGridSpec(a.grid, infos[0]);
        chosen = findGrid(infos[0], spec, where, true);
    } else {
        std::vector<uint8_t> nonEmpty(infos[0].size(), 0);
        for (size_t i = 0; i < count; ++i)
            for (const GridInfo& g : infos[i])
                if (const GridInfo* first = findGrid(infos[0], {g.name, g.index}, where, false))
                    nonEmpty[size_t(first - infos[0].data())] |= !g.empty;
        chosen = &chooseGrid(infos[0], nonEmpty, a.mode, where);
        spec = {chosen->name, std::nullopt};
        if (chosen->sameName > 1)
            spec.index = chosen->index;
    }
    if (!chosen->floating)
        throw UsageError("grid \"" + gridLabel(*chosen) + "\" of " + where + " has type " +
                         chosen->type + "; render needs a float or double grid");
    const bool levelSet = a.mode == "levelset" || (a.mode == "auto" && chosen->levelSet);
    if (levelSet && !chosen->levelSet)
        throw UsageError("grid \"" + gridLabel(*chosen) + "\" of " + where +
                         " is not a level set; render it with --mode fog");
    const std::string label = gridLabel(*chosen);

    // One box for every frame: the union of the frames' boxes of the chosen grid.
    BBoxd box;
    size_t reference = count;  // the frame with the largest box: it sets the extinction
    double referenceVolume = -1.0;
    for (size_t i = 0; i < count; ++i)
        forFrame(frameOf(i), [&] {
            const GridInfo* g = findGrid(infos[i], spec, inputOf(i), true);
            if (!g->floating)
                throw UsageError("grid \"" + label + "\" has type " + g->type +
                                 "; render needs a float or double grid");
            if (g->empty)
                return;
            box.expand(g->worldBox);
            const Vec3d e = g->worldBox.extents();
            if (e[0] * e[1] * e[2] > referenceVolume) {
                referenceVolume = e[0] * e[1] * e[2];
                reference = i;
            }
        });
    if (reference == count)
        throw UsageError("grid \"" + label + "\" of " + a.input +
                         (sequence ? " is empty in every frame" : " is empty") +
                         (levelSet ? "" : " (no positive density)") + ": nothing to render");
    const auto camera = makeCamera(a, box);

    // Fog: the extinction, from the reference frame unless given.
    double extinction = a.extinction;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (size_t i = 0; i < count; ++i)
        if (const GridInfo* g = findGrid(infos[i], spec, inputOf(i), false); g && !g->empty) {
            lo = std::min(lo, g->fog.minValue);
            hi = std::max(hi, g->fog.maxValue);
        }
    if (!levelSet && extinction < 0.0) {
        forFrame(frameOf(reference), [&] {
            GridBase::Ptr grid = findGrid(infos[reference], spec, inputOf(reference), true)->grid;
            if (!grid) {
                const GridPtrVec grids = report.step(
                    tag(reference) + "read " + inputOf(reference) + " (for the extinction)",
                    [&] { return readGrids(inputOf(reference), ctx); });
                grid =
                    findGrid(describeGrids(grids, true, threaded), spec, inputOf(reference), true)
                        ->grid;
            }
            withLevelSetGrid(grid, [&](const auto& g) {
                extinction =
                    render::suggestExtinction(g, *camera, kFogOpticalDepth, 0.9, 128, threaded);
            });
        });
        if (!(extinction > 0.0))  // no probe ray met the volume: from the box alone
            extinction = kFogOpticalDepth / (std::max(hi, 1e-30) * box.extents().length());
    }
    const double ambient = a.ambient >= 0.0 ? a.ambient : levelSet ? kSurfaceAmbient : kFogAmbient;
    // The light: given, or from the upper right of the camera and a little behind it, so that
    // one side of the subject is lit and the other in shadow.
    const Vec3d light = !a.light.empty() ? toVec(a.light)
                                         : camera->right() * kLightRight + camera->up() * kLightUp -
                                               camera->forward() * kLightBack;
    if (levelSet) {
        report.note("grid " + label + ": level set");
    } else {
        report.note("grid " + label + ": fog volume, values " + numberText(lo) + " to " +
                    numberText(hi) + "; extinction " + numberText(extinction) + " per world unit" +
                    (a.extinction < 0.0
                         ? " (derived: optical depth " + numberText(kFogOpticalDepth) +
                               " at the 90th percentile of the rays)"
                         : ""));
    }

    // Pass 2: render and write every frame.
    std::vector<std::string> outputs;
    for (size_t i = 0; i < count; ++i)
        forFrame(frameOf(i), [&] {
            GridBase::Ptr grid;
            if (const GridInfo* g = findGrid(infos[i], spec, inputOf(i), true); g->grid) {
                grid = g->grid;
            } else {
                const GridPtrVec grids = report.step(tag(i) + "read " + inputOf(i),
                                                     [&] { return readGrids(inputOf(i), ctx); });
                std::vector<GridInfo> again = describeGrids(grids, false, threaded);
                grid = findGrid(again, spec, inputOf(i), true)->grid;
            }
            render::Image image, normals;
            const render::Rgba bg =
                a.background.empty() ? render::Rgba{0.0f, 0.0f, 0.0f, 0.0f}
                                     : render::Rgba{float(a.background[0]), float(a.background[1]),
                                                    float(a.background[2]), 1.0f};
            withLevelSetGrid(grid, [&](const auto& g) {
                report.step(tag(i) + (levelSet ? "ray-trace " : "volume-render ") + label + " (" +
                                std::to_string(a.width) + "x" + std::to_string(a.height) + ")",
                            [&] {
                                if (levelSet) {
                                    render::LevelSetRenderSettings s;
                                    s.lightDirection = light;
                                    s.ambient = float(ambient);
                                    s.background = bg;
                                    s.threaded = threaded;
                                    image = render::renderLevelSet(
                                        g, *camera, s, a.normals.empty() ? nullptr : &normals);
                                } else {
                                    render::VolumeRenderSettings s;
                                    s.lightDirection = light;
                                    s.extinction = extinction;
                                    s.step = a.step;
                                    s.shadowStep = a.shadowStep;
                                    // As for surfaces: the sun brings 1 - ambient.
                                    const float sun = float(std::max(0.0, 1.0 - ambient));
                                    s.lightColor = render::Rgba{sun, sun, sun, 1.0f};
                                    s.ambientColor = render::Rgba{float(ambient), float(ambient),
                                                                  float(ambient), 1.0f};
                                    s.background = bg;
                                    s.threaded = threaded;
                                    image = render::renderFogVolume(g, *camera, s);
                                }
                            });
            });
            // A grid with something to show that covers no pixel: the camera misses it.
            if (!findGrid(infos[i], spec, inputOf(i), true)->empty && !covers(image, bg))
                throw UsageError("grid \"" + label +
                                 "\" covers no pixel of the picture: the "
                                 "camera does not see it (check --position, --look-at and "
                                 "--view); an empty picture is not written");
            const std::string out = outputFor(a.output, frameOf(i), "-o");
            report.step(tag(i) + "write " + out, [&] { writeImage(out, image); });
            if (levelSet && !a.normals.empty()) {
                const std::string n = outputFor(a.normals, frameOf(i), "--normals");
                report.step(tag(i) + "write " + n, [&] { writeImage(n, normals); });
            }
            outputs.push_back(out);
        });

    JsonWriter& json = report.json();
    json.key("input").value(a.input).key("grid").value(label).key("mode").value(
        levelSet ? "levelset" : "fog");
    json.key("width").value(static_cast<uint64_t>(a.width));
    json.key("height").value(static_cast<uint64_t>(a.height));
    json.key("output").value(a.output);
    if (!levelSet) {
        json.key("extinction").value(extinction);
        json.key("extinctionDerived").value(a.extinction < 0.0);
        json.key("valueRange").beginArray().value(lo).value(hi).endArray();
    }
    const auto vec = [&](const Vec3d& v) {
        json.beginArray().value(v[0]).value(v[1]).value(v[2]).endArray();
    };
    json.key("camera").beginObject().key("type").value(a.camera).key("position");
    vec(camera->position());
    json.key("forward");
    vec(camera->forward());
    json.key("up");
    vec(camera->up());
    if (const auto* p = dynamic_cast<const render::PerspectiveCamera*>(camera.get()))
        json.key("fov").value(2.0 * std::atan(p->tanHalfFov()) * 180.0 / std::numbers::pi);
    json.endObject();
    json.key("light");
    vec(light.unitSafe(0.0));
    json.key("ambient").value(ambient);
    if (sequence) {
        json.key("frames").beginArray();
        for (size_t i = 0; i < count; ++i)
            json.beginObject()
                .key("frame")
                .value(frames[i].number)
                .key("input")
                .value(frames[i].path)
                .key("output")
                .value(outputs[i])
                .endObject();
        json.endArray();
    }
    report.finish();
}

}  // namespace

void addRenderCommand(CLI::App& app, Context& ctx) {
    auto args = std::make_shared<RenderArgs>();
    CLI::App* cmd =
        addCommand(app, ctx, "render",
                   "Render a level set or a fog volume to a picture (PNG or EXR, alpha = coverage)",
                   true, [args, &ctx, &gridOption = args->gridOption] {
                       args->gridGiven = gridOption && gridOption->count() > 0;
                       runRender(*args, ctx);
                   });
    CLI::Option*& gridOption = args->gridOption;
    cmd->add_option("input", args->input,
                    "The .vdb file to read, or a frame sequence: a run of # in the file name "
                    "stands for the frame number (see below)")
        ->required();
    cmd->add_option("-o,--output", args->output,
                    "The picture to write: .png (8-bit sRGB, alpha) or .exr (32-bit float "
                    "linear RGBA, premultiplied), by extension; with # for a sequence")
        ->required();
    gridOption = cmd->add_option(
        "-g,--grid", args->grid,
        "The grid to render: NAME, or NAME[INDEX] for the INDEX-th (from 0, in file "
        "order) of several grids named NAME; '[0]' is an unnamed grid. Default: the "
        "first non-empty grid named density, then fog volume, level set, other "
        "float grid");
    cmd->add_option("--mode", args->mode, "auto (by grid class), levelset or fog")
        ->check(CLI::IsMember({"auto", "levelset", "fog"}))
        ->capture_default_str();
    cmd->add_option("--camera", args->camera, "perspective or ortho")
        ->check(CLI::IsMember({"perspective", "ortho"}))
        ->capture_default_str();
    cmd->add_option("--width", args->width, "Image width in pixels")
        ->check(CLI::Range(1, 16384))
        ->capture_default_str();
    cmd->add_option("--height", args->height, "Image height in pixels")
        ->check(CLI::Range(1, 16384))
        ->capture_default_str();
    cmd->add_option("--fov", args->fov, "Vertical field of view in degrees (perspective)")
        ->check(finiteRange(1.0, 179.0))
        ->capture_default_str();
    addVector(*cmd, "--view", args->view,
              "Viewing direction for automatic framing of the grid's box (fog: the box of "
              "positive densities; level set: of the active voxels)",
              true);
    addVector(*cmd, "--position", args->position, "Camera position (world units)", false);
    addVector(*cmd, "--look-at", args->lookAt, "Point the camera looks at, with --position", false);
    addVector(*cmd, "--up", args->up, "Up direction", true);
    addVector(*cmd, "--light", args->light,
              "World direction towards the light (the sun for fog); default: from the upper "
              "right of the camera, 0.45 right + 0.65 up + 0.6 back in its frame",
              false);
    cmd->add_option("--ambient", args->ambient,
                    "Light reaching every point, shadowed or not, relative to the light's "
                    "(default: 0.12 for surfaces, 0.3 for fog)")
        ->check(finiteRange(0.0, 100.0));
    cmd->add_option("--background", args->background,
                    "An opaque background colour R,G,B (linear, 0 to 1) instead of a "
                    "transparent one")
        ->expected(3)
        ->delimiter(',')
        ->check(finiteRange(0.0, 1e6))
        ->type_name("R,G,B");
    cmd->add_option("--normals", args->normals,
                    "Level sets: also write the surface normals as a picture");
    cmd->add_option("--extinction", args->extinction,
                    "Fog: extinction per world unit at density 1 (default: derived from the "
                    "data so that 90% of the rays that meet the volume reach an optical depth "
                    "of at most 4)")
        ->check(finiteRange(0.0, 1e30));
    cmd->add_option("--step", args->step, "Fog: longest primary step, in voxels")
        ->check(finiteRange(0.01, 100.0))
        ->capture_default_str();
    cmd->add_option("--shadow-step", args->shadowStep,
                    "Fog: longest step towards the light, in voxels")
        ->check(finiteRange(0.01, 100.0))
        ->capture_default_str();
    cmd->footer(
        "Frame sequences: in the input's file name a single # stands for a frame number of any "
        "number of digits (frame_#.vdb matches frame_1.vdb and frame_0001.vdb), a run of n # "
        "for one of at least n digits. Every matching file is rendered, in frame order, with "
        "one camera framed on the union of the frames' boxes and one extinction (from the "
        "frame with the largest box). In -o (and --normals) a single # is replaced by the "
        "frame number as the input file writes it, a run of n # by the number padded to n "
        "digits.\n\n"
        "Examples:\n  vdb render sphere.vdb -o sphere.png\n"
        "  vdb render smoke.vdb -o smoke.exr --grid density --width 640 --height 480\n"
        "  vdb render grids.vdb -o second.png --grid 'density[1]'\n"
        "  vdb render 'cache/fluid_data_#.vdb' -o 'frames/smoke_####.png'\n"
        "  vdb render bunny.vdb -o bunny.png --position 0,1,5 --look-at 0,0,0 --fov 30");
}

}  // namespace vdb::app
