// SPDX-License-Identifier: Apache-2.0
/// @file
/// Fog volume rendering, tool against tool: `vdb render` (this library's command-line tool)
/// against OpenVDB's `vdb_render` (Debian's libopenvdb-tools) on the real sample files, same
/// file, same picture size, same camera, settings matched as far as the two tools allow; whole
/// processes timed (reading, rendering, writing the picture), wall-clock and CPU seconds.
///
/// For each .vdb file of the sample folder that `vdb render` renders as a fog volume:
///   1. `vdb render FILE --json` with its defaults gives the grid, the derived extinction, the
///      camera (position, direction, up, vertical field of view) and the light direction;
///      vdb_render gets the same camera (-translate, -lookat, -up, -fov as the horizontal
///      field of view) and the same grid (-name).
///   2. Setting "vdb render defaults": ours as it is; vdb_render with the same extinction per
///      voxel (-scatter sigma * voxel size, -absorb 0), -step 0.5, -shadowstep 1, -gain 0
///      (no softening of shadows), -cutoff 0.001 and the same light direction.
///   3. Setting "vdb_render defaults": vdb_render as it is (extinction 1.6 per voxel, step 1,
///      shadow step 3, light 0.3,0.3,0, gain 0.2, cutoff 0.005); ours with --extinction
///      1.6 / voxel size, --step 1, --shadow-step 3, --light 0.3,0.3,0, --ambient 0.
/// The two tools alternate, run by run; medians of the runs; ratio = vdb render / vdb_render
/// in wall-clock seconds (below 1: this library is faster). vdb_render refuses grids whose
/// voxels are not cubes; those files are timed with this library alone.

#pragma once

#include <vdb/io/File.h>

#include "BenchCommon.h"
#include <fcntl.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

extern char** environ;

namespace vdb::bench {

/// What the comparison needs to know: where the tools and the files are, and how to run.
struct FogToolOptions {
    std::string samples;  ///< folder of .vdb files
    std::string vdbTool;  ///< this library's `vdb`
    std::string vdbRender = "/usr/bin/vdb_render";
    std::string pictures;  ///< folder for the last pictures of each run
    size_t width = 960, height = 720;
    int reps = 3;
};

/// One process run: wall-clock and CPU seconds (user + system), exit status, standard output.
struct ProcessRun {
    double wall = 0, cpu = 0;
    int status = -1;
    std::string out;
};

/// Runs `argv` with standard output to `outPath` (read back) and standard error discarded.
inline ProcessRun runProcess(const std::vector<std::string>& argv, const std::string& outPath) {
    std::vector<std::string> args(argv);
    std::vector<char*> cargv;
    for (auto& a : args)
        cargv.push_back(a.data());
    cargv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, outPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                     0644);
    posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
    ProcessRun run;
    pid_t pid = -1;
    const auto start = std::chrono::steady_clock::now();
    const int rc = posix_spawn(&pid, cargv[0], &actions, nullptr, cargv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (rc != 0)
        return run;
    int status = 0;
    rusage usage{};
    if (wait4(pid, &status, 0, &usage) != pid)
        return run;
    run.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    run.cpu = double(usage.ru_utime.tv_sec) + 1e-6 * double(usage.ru_utime.tv_usec) +
              double(usage.ru_stime.tv_sec) + 1e-6 * double(usage.ru_stime.tv_usec);
    run.status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    std::ifstream in(outPath);
    std::stringstream ss;
    ss << in.rdbuf();
    run.out = ss.str();
    return run;
}

/// The value of `"key": "..."` in a JSON document, or "".
inline std::string jsonString(const std::string& json, const std::string& key) {
    const size_t k = json.find("\"" + key + "\": \"");
    if (k == std::string::npos)
        return "";
    const size_t start = k + key.size() + 5;
    return json.substr(start, json.find('"', start) - start);
}

/// The numbers after `"key": ` (one, or the elements of an array), in order.
inline std::vector<double> jsonNumbers(const std::string& json, const std::string& key) {
    std::vector<double> out;
    size_t p = json.find("\"" + key + "\": ");
    if (p == std::string::npos)
        return out;
    p += key.size() + 4;
    const bool array = json[p] == '[';
    const size_t end = array ? json.find(']', p) : json.find_first_of(",\n}", p);
    std::string text = json.substr(p + (array ? 1 : 0), end - p - (array ? 1 : 0));
    std::replace(text.begin(), text.end(), ',', ' ');
    std::istringstream in(text);
    double x;
    while (in >> x)
        out.push_back(x);
    return out;
}

inline std::string joined(const std::vector<double>& v) {
    std::string s;
    for (double x : v) {
        char buf[40];
        std::snprintf(buf, sizeof buf, "%.17g", x);
        s += (s.empty() ? "" : ",") + std::string(buf);
    }
    return s;
}

/// Runs the comparison of the file comment, printing a line per run to stdout and adding its
/// tables and notes to `md`; `ratios` receives every wall-clock ratio. Returns false when a
/// tool failed on a file it should render.
inline bool compareFogTools(const FogToolOptions& o, MarkdownReport& md, RatioRange& ratios,
                            double target) {
    namespace fs = std::filesystem;
    std::error_code ec;
    std::vector<std::string> files;
    for (const auto& e : fs::directory_iterator(o.samples, ec))
        if (e.path().extension() == ".vdb")
            files.push_back(e.path().string());
    std::sort(files.begin(), files.end());
    fs::create_directories(o.pictures, ec);
    const std::string size = std::to_string(o.width) + "x" + std::to_string(o.height);
    const std::string scratch = o.pictures + "/stdout.txt";
    std::vector<MarkdownReport::Row> rows;
    std::vector<std::string> skipped, ownOnly;
    bool ok = true;
    std::printf("# fog volumes: vdb render against vdb_render, %s, medians of %d runs\n",
                size.c_str(), o.reps);
    std::printf("%-26s %-18s %-22s %9s %9s %6s %9s %9s\n", "file", "grid", "setting", "vdb s",
                "vdb_rnd s", "ratio", "vdb cpu", "vdb_r cpu");
    for (const std::string& file : files) {
        const std::string base = fs::path(file).stem().string();
        const std::string ours = o.pictures + "/" + base + "-vdb.png";
        const ProcessRun probe =
            runProcess({o.vdbTool, "render", file, "-o", ours, "--width", std::to_string(o.width),
                        "--height", std::to_string(o.height), "--json", "--quiet"},
                       scratch);
        const std::string grid = jsonString(probe.out, "grid");
        if (probe.status != 0 || jsonString(probe.out, "mode") != "fog") {
            skipped.push_back(fs::path(file).filename().string() +
                              (probe.status != 0 ? " (nothing to render)" : " (level set)"));
            continue;
        }
        // The grid's voxel size, for extinctions per voxel, and whether vdb_render can read it.
        double voxel = 0.0;
        bool cubic = false;
        try {
            io::File in(file);
            in.open();
            size_t index = 0;
            const std::string name = grid.substr(0, grid.find('['));
            if (grid.find('[') != std::string::npos)
                index = size_t(std::stoul(grid.substr(grid.find('[') + 1)));
            const auto grids = in.getGrids();
            for (const auto& g : *grids) {
                if (g->getName() != name)
                    continue;
                if (index-- == 0) {
                    voxel = g->voxelSize()[0];
                    cubic = g->transform().hasUniformScale();
                    break;
                }
            }
        } catch (const std::exception& e) {
            std::fprintf(stderr, "%s: %s\n", file.c_str(), e.what());
            ok = false;
            continue;
        }
        const std::vector<double> position = jsonNumbers(probe.out, "position"),
                                  forward = jsonNumbers(probe.out, "forward"),
                                  up = jsonNumbers(probe.out, "up"),
                                  light = jsonNumbers(probe.out, "light"),
                                  fov = jsonNumbers(probe.out, "fov"),
                                  extinction = jsonNumbers(probe.out, "extinction");
        if (position.size() != 3 || forward.size() != 3 || up.size() != 3 || light.size() != 3 ||
            fov.empty() || extinction.empty() || !(voxel > 0.0)) {
            std::fprintf(stderr, "%s: unexpected report from vdb render\n", file.c_str());
            ok = false;
            continue;
        }
        std::vector<double> lookAt(3);
        for (int i = 0; i < 3; ++i)
            lookAt[size_t(i)] = position[size_t(i)] + forward[size_t(i)];
        const double pi = 3.14159265358979323846;
        const double horizontal =
            2.0 *
            std::atan(std::tan(0.5 * fov[0] * pi / 180.0) * double(o.width) / double(o.height)) *
            180.0 / pi;
        const std::string sigma = joined({extinction[0] * voxel});
        const std::vector<std::string> camera{"-res",       size,
                                              "-translate", joined(position),
                                              "-lookat",    joined(lookAt),
                                              "-up",        joined(up),
                                              "-fov",       joined({horizontal}),
                                              "-name",      grid.substr(0, grid.find('['))};
        struct Setting {
            std::string name;
            std::vector<std::string> ours, theirs;
        };
        std::vector<Setting> settings(2);
        settings[0].name = "vdb render defaults";
        settings[0].theirs = {"-absorb",     "0,0,0",
                              "-scatter",    sigma + "," + sigma + "," + sigma,
                              "-step",       "0.5",
                              "-shadowstep", "1",
                              "-gain",       "0",
                              "-cutoff",     "0.001",
                              "-light",      joined(light) + ",0.7,0.7,0.7"};
        settings[1].name = "vdb_render defaults";
        settings[1].ours = {
            "--extinction", joined({1.6 / voxel}), "--step",    "1", "--shadow-step", "3",
            "--light",      "0.3,0.3,0",           "--ambient", "0"};
        for (const Setting& s : settings) {
            std::vector<double> wallA, wallB, cpuA, cpuB;
            for (int r = 0; r < o.reps; ++r) {
                std::vector<std::string> a{o.vdbTool,
                                           "render",
                                           file,
                                           "-o",
                                           ours,
                                           "--width",
                                           std::to_string(o.width),
                                           "--height",
                                           std::to_string(o.height),
                                           "--quiet"};
                a.insert(a.end(), s.ours.begin(), s.ours.end());
                const ProcessRun ra = runProcess(a, scratch);
                if (ra.status != 0) {
                    std::fprintf(stderr, "%s: vdb render failed (%d)\n", file.c_str(), ra.status);
                    ok = false;
                }
                wallA.push_back(ra.wall);
                cpuA.push_back(ra.cpu);
                if (!cubic)
                    continue;
                std::vector<std::string> b{o.vdbRender, file,
                                           o.pictures + "/" + base + "-vdb_render.png"};
                b.insert(b.end(), camera.begin(), camera.end());
                b.insert(b.end(), s.theirs.begin(), s.theirs.end());
                const ProcessRun rb = runProcess(b, scratch);
                if (rb.status != 0) {
                    std::fprintf(stderr, "%s: vdb_render failed (%d)\n", file.c_str(), rb.status);
                    ok = false;
                }
                wallB.push_back(rb.wall);
                cpuB.push_back(rb.cpu);
            }
            // Keep the pictures of the last run of each setting.
            const std::string tag = &s == &settings[0] ? "a" : "b";
            fs::copy_file(ours, o.pictures + "/" + base + "-" + tag + "-vdb.png",
                          fs::copy_options::overwrite_existing, ec);
            if (cubic)
                fs::copy_file(o.pictures + "/" + base + "-vdb_render.png",
                              o.pictures + "/" + base + "-" + tag + "-vdb_render.png",
                              fs::copy_options::overwrite_existing, ec);
            const double a = median(wallA), b = median(wallB);
            const double ca = median(cpuA), cb = median(cpuB);
            const double ratio = cubic ? a / b : std::nan("");
            if (cubic)
                ratios.add(ratio);
            std::printf("%-26s %-18s %-22s %9.3f %9.3f %6.2f %9.3f %9.3f\n",
                        fs::path(file).filename().string().c_str(), grid.c_str(), s.name.c_str(), a,
                        b, ratio, ca, cb);
            std::fflush(stdout);
            const bool first = &s == &settings[0];
            rows.push_back({first ? fs::path(file).filename().string() : "", first ? grid : "",
                            first ? fmt(voxel, 4) : "", s.name, fmt(a, 2),
                            cubic ? fmt(b, 2) : "refused", cubic ? ratioCell(ratio, target) : "",
                            fmt(ca, 2), cubic ? fmt(cb, 2) : ""});
        }
        if (!cubic)
            ownOnly.push_back(fs::path(file).filename().string());
    }
    char line[512];
    std::snprintf(line, sizeof line,
                  "Fog volumes, tool against tool: whole `vdb render` and `vdb_render` processes "
                  "(read, render, write the PNG) at %s on every sample file that `vdb render` "
                  "renders as a fog volume, same camera and grid, medians of %d runs, the tools "
                  "alternating. Ratio = vdb render / vdb_render in wall-clock seconds, in bold "
                  "where it meets the target (at most %.2f); CPU seconds are user + system of "
                  "the process.",
                  size.c_str(), o.reps, target);
    md.paragraph(line);
    md.table({"file", "grid", "voxel", "settings", "vdb render s", "vdb_render s", "ratio",
              "vdb render CPU s", "vdb_render CPU s"},
             rows);
    if (!ownOnly.empty()) {
        std::string names;
        for (const auto& n : ownOnly)
            names += (names.empty() ? "" : ", ") + n;
        md.paragraph("vdb_render refuses " + names +
                     " (\"VolumeRayIntersector only supports uniform voxels\"): the voxels of "
                     "their grids are not cubes. This library's times are shown alone.");
    }
    if (!skipped.empty()) {
        std::string names;
        for (const auto& n : skipped)
            names += (names.empty() ? "" : ", ") + n;
        md.paragraph("Not fog volumes for `vdb render`: " + names + ".");
    }
    return ok;
}

}  // namespace vdb::bench
