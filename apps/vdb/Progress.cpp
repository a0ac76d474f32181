// SPDX-License-Identifier: Apache-2.0

#include "Progress.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace vdb::app {

bool progressWanted(bool quiet) {
    return !quiet && ::isatty(STDERR_FILENO) == 1;
}

Progress::Progress(bool enabled, std::string label, uint64_t total)
    : mLabel(std::move(label)),
      mTotal(total),
      mStart(std::chrono::steady_clock::now()),
      mEnabled(enabled) {
    if (mEnabled)
        mThread = std::thread([this] { run(); });
}

Progress::~Progress() {
    finish();
}

double Progress::elapsed() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - mStart).count();
}

double Progress::finish() {
    if (mFinished >= 0)
        return mFinished;
    mFinished = elapsed();
    if (mThread.joinable()) {
        {
            std::lock_guard lock(mMutex);
            mStop = true;
        }
        mWake.notify_all();
        mThread.join();
        std::fputs("\r\033[K", stderr);  // clear the line
        std::fflush(stderr);
    }
    return mFinished;
}

void Progress::run() {
    std::unique_lock lock(mMutex);
    // Short steps finish before anything is drawn.
    if (mWake.wait_for(lock, std::chrono::milliseconds(250), [this] { return mStop; }))
        return;
    while (!mStop) {
        draw();
        mWake.wait_for(lock, std::chrono::milliseconds(100), [this] { return mStop; });
    }
}

void Progress::draw() {
    const double seconds = elapsed();
    char line[256];
    if (mTotal == 0) {
        static const char kSpin[] = "|/-\\";
        const int frame = static_cast<int>(seconds * 10) % 4;
        std::snprintf(line, sizeof line, "\r%c %s  %.1f s\033[K", kSpin[frame], mLabel.c_str(),
                      seconds);
    } else {
        const double fraction =
            std::min(1.0, static_cast<double>(mDone.load(std::memory_order_relaxed)) /
                              static_cast<double>(mTotal));
        constexpr int kWidth = 24;
        char bar[kWidth + 1];
        const int filled = static_cast<int>(fraction * kWidth);
        for (int i = 0; i < kWidth; ++i)
            bar[i] = i < filled ? '#' : '.';
        bar[kWidth] = '\0';
        if (fraction > 0.01) {
            const double eta = seconds * (1 - fraction) / fraction;
            std::snprintf(line, sizeof line, "\r%s [%s] %3d%%  %.1f s, about %.0f s left\033[K",
                          mLabel.c_str(), bar, static_cast<int>(fraction * 100), seconds, eta);
        } else {
            std::snprintf(line, sizeof line, "\r%s [%s] %3d%%  %.1f s\033[K", mLabel.c_str(), bar,
                          static_cast<int>(fraction * 100), seconds);
        }
    }
    std::fputs(line, stderr);
    std::fflush(stderr);
}

}  // namespace vdb::app
