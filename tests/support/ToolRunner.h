// SPDX-License-Identifier: Apache-2.0
/// @file
/// Runs the `vdb` command-line tool from a test: standard input from /dev/null, standard output
/// and error captured in files of a folder, exit status (or 128 + signal) returned.

#pragma once

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

extern char** environ;

namespace vdb::test {

/// What a finished run of the tool left.
struct Result {
    int status = -1;  ///< exit status, or 128 + the signal that ended it
    std::string out;  ///< standard output
    std::string err;  ///< standard error
};

/// Starts `tool` with `args`, its output going to stdout.txt and stderr.txt in `dir`; returns
/// the process id, or -1 when it cannot start.
inline pid_t spawnTool(const std::string& tool, const std::vector<std::string>& args,
                       const std::string& dir) {
    std::vector<std::string> argv{tool};
    argv.insert(argv.end(), args.begin(), args.end());
    std::vector<char*> cargv;
    for (auto& a : argv)
        cargv.push_back(a.data());
    cargv.push_back(nullptr);
    const std::string out = dir + "/stdout.txt", err = dir + "/stderr.txt";
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, out.c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, err.c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0644);
    pid_t pid = -1;
    const int rc = posix_spawn(&pid, tool.c_str(), &actions, nullptr, cargv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    return rc == 0 ? pid : -1;
}

/// Waits for `pid` (from spawnTool with the same `dir`) and collects its output, removing the
/// output files.
inline Result waitTool(pid_t pid, const std::string& dir) {
    const auto slurp = [](const std::string& path) {
        std::ifstream in(path);
        std::stringstream ss;
        ss << in.rdbuf();
        return ss.str();
    };
    Result r;
    int status = 0;
    if (pid > 0 && ::waitpid(pid, &status, 0) == pid)
        r.status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    r.out = slurp(dir + "/stdout.txt");
    r.err = slurp(dir + "/stderr.txt");
    std::error_code ec;
    std::filesystem::remove(dir + "/stdout.txt", ec);
    std::filesystem::remove(dir + "/stderr.txt", ec);
    return r;
}

/// Runs `tool` with `args` to the end.
inline Result runTool(const std::string& tool, const std::vector<std::string>& args,
                      const std::string& dir) {
    return waitTool(spawnTool(tool, args, dir), dir);
}

}  // namespace vdb::test
