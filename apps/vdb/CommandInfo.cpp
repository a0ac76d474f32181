// SPDX-License-Identifier: Apache-2.0
/// @file
/// `vdb info FILE...`: what each file holds: its version, metadata and, per grid, type,
/// class, voxel and leaf counts, bounding boxes, voxel size, memory and storage settings.

#include "Commands.h"

#include <cstdio>
#include <filesystem>
#include <sstream>
#include <variant>

namespace vdb::app {
namespace {

std::string coordText(const Coord& c) {
    return "(" + std::to_string(c[0]) + ", " + std::to_string(c[1]) + ", " + std::to_string(c[2]) +
           ")";
}

template <typename Vec3T>
std::string vecText(const Vec3T& v) {
    std::ostringstream os;
    os << "(" << v[0] << ", " << v[1] << ", " << v[2] << ")";
    return os.str();
}

std::string metaText(const MetaValue& value) {
    return std::visit(
        [](const auto& v) -> std::string {
            using T = std::decay_t<decltype(v)>;
            if constexpr (std::is_same_v<T, std::string>)
                return "\"" + v + "\"";
            else if constexpr (std::is_same_v<T, bool>)
                return v ? "true" : "false";
            else if constexpr (std::is_same_v<T, OpaqueMetadata>)
                return "<" + std::to_string(v.bytes.size()) + " bytes of " + v.typeName + ">";
            else if constexpr (std::is_arithmetic_v<T>) {
                std::ostringstream os;
                os << v;
                return os.str();
            } else
                return vecText(v);
        },
        value);
}

void metaJson(JsonWriter& json, const MetaValue& value) {
    std::visit(
        [&json](const auto& v) {
            using T = std::decay_t<decltype(v)>;
            if constexpr (std::is_same_v<T, OpaqueMetadata>)
                json.beginObject()
                    .key("type")
                    .value(v.typeName)
                    .key("bytes")
                    .value(static_cast<uint64_t>(v.bytes.size()))
                    .endObject();
            else if constexpr (std::is_same_v<T, std::string> || std::is_same_v<T, bool>)
                json.value(v);
            else if constexpr (std::is_integral_v<T>)
                json.value(static_cast<int64_t>(v));
            else if constexpr (std::is_floating_point_v<T>)
                json.value(static_cast<double>(v));
            else
                json.triple(v);
        },
        value);
}

void metaMapJson(JsonWriter& json, const MetaMap& meta) {
    json.beginObject();
    for (const auto& [name, value] : meta.metadata()) {
        json.key(name);
        metaJson(json, value);
    }
    json.endObject();
}

std::string storageText(const GridBase& grid) {
    std::string text;
    if (const auto* c = grid.getMeta<std::string>("file_compression"))
        text = *c;
    if (grid.saveFloatAsHalf())
        text += text.empty() ? "half floats" : ", half floats";
    return text.empty() ? "-" : text;
}

void printGrid(const GridBase& grid, bool longForm) {
    const CoordBBox bbox = grid.evalActiveVoxelBoundingBox();
    std::printf("  %s\n", grid.getName().empty() ? "(no name)" : grid.getName().c_str());
    std::printf("    type            %s (%s values), class %s\n", grid.type().c_str(),
                grid.valueType().c_str(),
                std::string(gridClassToString(grid.getGridClass())).c_str());
    std::printf("    active voxels   %s in %s leaves\n",
                withCommas(grid.activeVoxelCount()).c_str(), withCommas(grid.leafCount()).c_str());
    if (bbox.empty()) {
        std::printf("    bounding box    empty\n");
    } else {
        const auto ext = bbox.extents();
        std::printf("    index bbox      %s to %s, %lld x %lld x %lld\n",
                    coordText(bbox.min()).c_str(), coordText(bbox.max()).c_str(),
                    static_cast<long long>(ext[0]), static_cast<long long>(ext[1]),
                    static_cast<long long>(ext[2]));
        const auto world = grid.transform().indexToWorld(bbox);
        std::printf("    world bbox      %s to %s\n", vecText(world.min()).c_str(),
                    vecText(world.max()).c_str());
    }
    std::printf("    voxel size      %s (%s map)\n", vecText(grid.voxelSize()).c_str(),
                std::string(grid.transform().mapTypeName()).c_str());
    std::printf("    memory          %s\n", bytesText(grid.memUsage()).c_str());
    std::printf("    stored as       %s\n", storageText(grid).c_str());
    if (longForm && grid.metaCount() > 0) {
        std::printf("    metadata\n");
        for (const auto& [name, value] : grid.metadata())
            std::printf("      %-28s %s\n", name.c_str(), metaText(value).c_str());
    }
}

void gridJson(JsonWriter& json, const GridBase& grid) {
    const CoordBBox bbox = grid.evalActiveVoxelBoundingBox();
    json.beginObject()
        .key("name")
        .value(grid.getName())
        .key("type")
        .value(grid.type())
        .key("valueType")
        .value(grid.valueType())
        .key("class")
        .value(std::string(gridClassToString(grid.getGridClass())))
        .key("activeVoxels")
        .value(static_cast<uint64_t>(grid.activeVoxelCount()))
        .key("leaves")
        .value(static_cast<uint64_t>(grid.leafCount()));
    if (bbox.empty()) {
        json.key("indexBBox").null().key("worldBBox").null();
    } else {
        const auto world = grid.transform().indexToWorld(bbox);
        json.key("indexBBox").beginArray().triple(bbox.min()).triple(bbox.max()).endArray();
        json.key("worldBBox").beginArray().triple(world.min()).triple(world.max()).endArray();
    }
    json.key("voxelSize").triple(grid.voxelSize());
    json.key("mapType").value(std::string(grid.transform().mapTypeName()));
    json.key("memoryBytes").value(static_cast<uint64_t>(grid.memUsage()));
    json.key("halfFloat").value(grid.saveFloatAsHalf());
    json.key("metadata");
    metaMapJson(json, grid);
    json.endObject();
}

}  // namespace

void addInfoCommand(CLI::App& app, Context& ctx) {
    struct Args {
        std::vector<std::string> files;
        bool longForm = false;
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd = addCommand(
        app, ctx, "info", "Show the grids of .vdb files: types, counts, bounds, memory, metadata",
        true, [args, &ctx] {
            Report report(ctx);
            JsonWriter& json = report.json();
            json.key("files").beginArray();
            for (const std::string& path : args->files) {
                io::File file(path);
                const GridPtrVec grids = report.step("read " + path, [&] {
                    file.open();
                    return *file.getGrids();
                });
                warnAboutFileVersion(file, ctx);
                const MetaMap fileMeta = file.getMetadata();
                std::error_code ec;
                const auto size = std::filesystem::file_size(path, ec);
                const auto [major, minor] = file.libraryVersion();
                if (ctx.verbose()) {
                    std::printf("%s: %s, file version %u, written by library %u.%u, %zu grid%s\n",
                                path.c_str(), bytesText(ec ? 0 : size).c_str(), file.fileVersion(),
                                major, minor, grids.size(), grids.size() == 1 ? "" : "s");
                    if (args->longForm)
                        for (const auto& [name, value] : fileMeta.metadata())
                            std::printf("  %-30s %s\n", name.c_str(), metaText(value).c_str());
                    for (const auto& grid : grids)
                        printGrid(*grid, args->longForm);
                    for (const auto& skipped : file.unsupportedGrids())
                        std::printf("  %s\n    type            %s (not supported: skipped)\n",
                                    skipped.name.c_str(), skipped.type.c_str());
                }
                json.beginObject()
                    .key("path")
                    .value(path)
                    .key("bytes")
                    .value(static_cast<uint64_t>(ec ? 0 : size))
                    .key("fileVersion")
                    .value(file.fileVersion())
                    .key("libraryVersion")
                    .value(std::to_string(major) + "." + std::to_string(minor))
                    .key("metadata");
                metaMapJson(json, fileMeta);
                json.key("grids").beginArray();
                for (const auto& grid : grids)
                    gridJson(json, *grid);
                json.endArray().key("unsupportedGrids").beginArray();
                for (const auto& skipped : file.unsupportedGrids())
                    json.beginObject()
                        .key("name")
                        .value(skipped.name)
                        .key("type")
                        .value(skipped.type)
                        .endObject();
                json.endArray().endObject();
            }
            json.endArray();
            report.finish();
        });
    cmd->add_option("files", args->files, ".vdb files to describe")->required();
    cmd->add_flag("-l,--long", args->longForm, "Also list the file and grid metadata");
    cmd->footer("Example:\n  vdb info -l smoke.vdb\n  vdb info --json a.vdb b.vdb");
}

}  // namespace vdb::app
