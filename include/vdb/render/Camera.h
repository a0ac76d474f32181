// SPDX-License-Identifier: Apache-2.0
/// @file
/// Cameras that turn image positions into world-space rays: PerspectiveCamera (a pinhole with a
/// vertical field of view) and OrthographicCamera (parallel rays through a window of given
/// height), each placed by position, look-at point and up vector, or framed automatically
/// around a world-space box.
///
/// Image positions are continuous pixel coordinates: x from 0 at the left edge to width() at
/// the right, y from 0 at the top edge to height() at the bottom; the centre of pixel (i, j) is
/// (i + 0.5, j + 0.5).
///
/// @code
/// auto camera = vdb::render::PerspectiveCamera::frame(
///     grid.transform().indexToWorld(grid.evalActiveVoxelBoundingBox()), 640, 480,
///     /*viewDirection=*/vdb::Vec3d(-1, -0.5, -1));
/// vdb::math::Ray<double> ray = camera.ray(320.5, 240.5);   // through the image centre
/// @endcode

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/math/BBox.h>
#include <vdb/math/Ray.h>
#include <vdb/math/Vec3.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>

namespace vdb::render {

/// A camera's image size and orthonormal frame; the base of the two projections.
///
/// Invariant: forward(), right() and up() are orthonormal, right = forward x upHint normalized,
/// and width(), height() are positive.
/// Threads: a plain value; concurrent const calls are safe.
class Camera {
public:
    virtual ~Camera() = default;

    size_t width() const { return mWidth; }
    size_t height() const { return mHeight; }
    const Vec3d& position() const { return mPosition; }
    /// Unit vectors: the view direction, and the image's right and up directions.
    const Vec3d& forward() const { return mForward; }
    const Vec3d& right() const { return mRight; }
    const Vec3d& up() const { return mUp; }

    /// The world-space ray through the image position (x, y), with a unit direction.
    virtual math::Ray<double> ray(double x, double y) const = 0;

protected:
    /// @throw ValueError for an empty image, position == lookAt, or `up` along the view.
    Camera(size_t width, size_t height, const Vec3d& position, const Vec3d& lookAt, const Vec3d& up)
        : mWidth(width), mHeight(height), mPosition(position) {
        if (width == 0 || height == 0)
            throw ValueError("Camera: the image must have at least one pixel");
        const Vec3d view = lookAt - position;
        if (!(view.length() > 0.0))
            throw ValueError("Camera: the look-at point must differ from the position");
        mForward = view.unitSafe(0.0);
        mRight = mForward.cross(up);
        if (!mRight.normalize(1e-12 * up.length()))
            throw ValueError("Camera: the up vector must not be parallel to the view direction");
        mUp = mRight.cross(mForward);
    }
    Camera(const Camera&) = default;
    Camera& operator=(const Camera&) = default;

    /// Maps the image position (x, y) to [-aspect, aspect] x [-1, 1] (y up), aspect =
    /// width / height.
    void screen(double x, double y, double& sx, double& sy) const {
        const double h = double(mHeight);
        sx = (2.0 * x - double(mWidth)) / h;
        sy = (h - 2.0 * y) / h;
    }
    double aspect() const { return double(mWidth) / double(mHeight); }

private:
    size_t mWidth, mHeight;
    Vec3d mPosition, mForward, mRight, mUp;
};

/// A pinhole camera: rays start at position() and pass through a window at unit distance
/// whose height spans the vertical field of view.
class PerspectiveCamera : public Camera {
public:
    /// @param fovDegrees  the vertical field of view, in (0, 180) degrees.
    /// @throw ValueError for a field of view outside (0, 180), and as Camera.
    PerspectiveCamera(size_t width, size_t height, const Vec3d& position, const Vec3d& lookAt,
                      const Vec3d& up = Vec3d(0, 1, 0), double fovDegrees = 40.0)
        : Camera(width, height, position, lookAt, up) {
        if (!(fovDegrees > 0.0 && fovDegrees < 180.0))
            throw ValueError("PerspectiveCamera: the field of view must lie in (0, 180) degrees");
        mTanHalfFov = std::tan(0.5 * fovDegrees * std::numbers::pi / 180.0);
    }

    /// A camera looking along `viewDirection` at the centre of `worldBox`, as close as it can
    /// be while the sphere around the box stays inside both fields of view.
    /// @throw ValueError for an empty box or a zero view direction, and as above.
    static PerspectiveCamera frame(const BBoxd& worldBox, size_t width, size_t height,
                                   const Vec3d& viewDirection = Vec3d(0, 0, -1),
                                   double fovDegrees = 40.0, const Vec3d& up = Vec3d(0, 1, 0));

    math::Ray<double> ray(double x, double y) const override {
        double sx, sy;
        screen(x, y, sx, sy);
        const Vec3d dir = forward() + right() * (sx * mTanHalfFov) + up() * (sy * mTanHalfFov);
        return math::Ray<double>(position(), dir.unitSafe(0.0), 0.0);
    }
    /// tan(vertical field of view / 2).
    double tanHalfFov() const { return mTanHalfFov; }

private:
    double mTanHalfFov;
};

/// Parallel rays along forward(), starting on the plane through position(), through a window of
/// frameHeight() world units (and width frameHeight() * width / height).
class OrthographicCamera : public Camera {
public:
    /// @throw ValueError for a frame height that is not positive, and as Camera.
    OrthographicCamera(size_t width, size_t height, const Vec3d& position, const Vec3d& lookAt,
                       const Vec3d& up = Vec3d(0, 1, 0), double frameHeight = 1.0)
        : Camera(width, height, position, lookAt, up), mFrameHeight(frameHeight) {
        if (!(frameHeight > 0.0))
            throw ValueError("OrthographicCamera: the frame height must be positive");
    }

    /// A camera looking along `viewDirection` whose window holds the sphere around `worldBox`,
    /// starting outside that sphere.
    /// @throw ValueError for an empty box or a zero view direction, and as above.
    static OrthographicCamera frame(const BBoxd& worldBox, size_t width, size_t height,
                                    const Vec3d& viewDirection = Vec3d(0, 0, -1),
                                    const Vec3d& up = Vec3d(0, 1, 0));

    math::Ray<double> ray(double x, double y) const override {
        double sx, sy;
        screen(x, y, sx, sy);
        const double half = 0.5 * mFrameHeight;
        const Vec3d eye = position() + right() * (sx * half) + up() * (sy * half);
        return math::Ray<double>(eye, forward(), 0.0);
    }
    double frameHeight() const { return mFrameHeight; }

private:
    double mFrameHeight;
};

// ---- Implementation ---------------------------------------------------------------------------

namespace detail {

/// The centre and the radius of the sphere around `box`; throws for an empty box.
inline void boundingSphere(const BBoxd& box, Vec3d& center, double& radius) {
    if (box.empty())
        throw ValueError("Camera::frame: the box is empty");
    center = box.center();
    radius = std::max(0.5 * box.extents().length(), 1e-12);
}

inline Vec3d unitView(const Vec3d& viewDirection) {
    Vec3d v = viewDirection;
    if (!v.normalize(0.0))
        throw ValueError("Camera::frame: the view direction is zero");
    return v;
}

}  // namespace detail

inline PerspectiveCamera PerspectiveCamera::frame(const BBoxd& worldBox, size_t width,
                                                  size_t height, const Vec3d& viewDirection,
                                                  double fovDegrees, const Vec3d& up) {
    Vec3d center;
    double radius;
    detail::boundingSphere(worldBox, center, radius);
    const Vec3d view = detail::unitView(viewDirection);
    if (!(fovDegrees > 0.0 && fovDegrees < 180.0))
        throw ValueError("PerspectiveCamera: the field of view must lie in (0, 180) degrees");
    // The narrower of the two half angles must see the whole sphere: sin(half) = r / d.
    const double tanV = std::tan(0.5 * fovDegrees * std::numbers::pi / 180.0);
    const double tanH = tanV * (height ? double(width) / double(height) : 1.0);
    const double half = std::atan(std::min(tanV, tanH));
    const double distance = radius / std::sin(half);
    return PerspectiveCamera(width, height, center - view * distance, center, up, fovDegrees);
}

inline OrthographicCamera OrthographicCamera::frame(const BBoxd& worldBox, size_t width,
                                                    size_t height, const Vec3d& viewDirection,
                                                    const Vec3d& up) {
    Vec3d center;
    double radius;
    detail::boundingSphere(worldBox, center, radius);
    const Vec3d view = detail::unitView(viewDirection);
    const double aspect = height ? double(width) / double(height) : 1.0;
    const double frameHeight = 2.0 * radius * std::max(1.0, 1.0 / aspect);
    return OrthographicCamera(width, height, center - view * (2.0 * radius), center, up,
                              frameHeight);
}

}  // namespace vdb::render
