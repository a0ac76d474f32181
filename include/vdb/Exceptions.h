// SPDX-License-Identifier: Apache-2.0
/// @file
/// The typed exceptions the library throws. The library never prints or exits: callers catch these.

#pragma once

#include <stdexcept>
#include <string>

namespace vdb {

/// Base of every exception the library throws.
class Exception : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// A coordinate or index outside the domain an operation accepts (for example a write
/// outside the fixed domain of a tree whose top is an InternalNode).
class IndexError : public Exception {
public:
    using Exception::Exception;
};

/// An argument whose value makes no sense for the operation.
class ValueError : public Exception {
public:
    using Exception::Exception;
};

/// A grid or value of the wrong type for the operation.
class TypeError : public Exception {
public:
    using Exception::Exception;
};

/// A read or write failure: a missing, truncated, corrupt or unsupported file. The message
/// names the file and the reason.
class IoError : public Exception {
public:
    using Exception::Exception;
};

/// An operation that was stopped on request (for example by a progress callback).
class CancelledError : public Exception {
public:
    using Exception::Exception;
};

}  // namespace vdb
