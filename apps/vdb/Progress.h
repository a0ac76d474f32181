// SPDX-License-Identifier: Apache-2.0
/// @file
/// Progress display for long operations: on a terminal, one line on stderr redrawn ten times a
/// second with the elapsed time, and for work of known size a bar, a percentage and an
/// estimate of the time left. Silent when stderr is not a terminal or with --quiet.

#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>

namespace vdb::app {

/// One step of a command ("Reading a.vdb", "Dilating"), timed from construction.
/// Threads: advance() and set() may be called from any thread.
class Progress {
public:
    /// `total` is the amount of work in any unit (0: unknown; only the elapsed time is shown).
    Progress(bool enabled, std::string label, uint64_t total = 0);
    ~Progress();
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;

    void advance(uint64_t amount = 1) { mDone.fetch_add(amount, std::memory_order_relaxed); }
    void set(uint64_t done) { mDone.store(done, std::memory_order_relaxed); }
    /// Seconds since construction.
    double elapsed() const;
    /// Clears the line and returns the elapsed seconds; later calls return the same.
    double finish();

private:
    void draw();
    void run();

    std::string mLabel;
    uint64_t mTotal;
    std::atomic<uint64_t> mDone{0};
    std::chrono::steady_clock::time_point mStart;
    double mFinished = -1;
    bool mEnabled;
    std::mutex mMutex;
    std::condition_variable mWake;
    bool mStop = false;
    std::thread mThread;
};

/// Whether progress lines should be drawn: stderr is a terminal and not `quiet`.
bool progressWanted(bool quiet);

}  // namespace vdb::app
