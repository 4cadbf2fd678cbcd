#pragma once
// Turning the frames of Weber & Penn's stems and leaves (§4.1–4.3, §4.8): rotations about a frame's
// own axes and the tree's vertical, a child's orientation on its parent, and the turns that keep a
// stem up and above the ground. Internal to the Weber–Penn builder.

#include "core/math.h"
#include "geometry/trees/weber_penn/weber_penn.h"

namespace sylva::wp {

// Rotations of a frame about its own axes, right-handed, angles in radians.
Frame rotate_x(const Frame& f, float a);
Frame rotate_y(const Frame& f, float a);
Frame rotate_z(const Frame& f, float a);
// Rotation of a frame about the unit axis k.
Frame rotate_axis(const Frame& f, const Vec3& k, float a);
// Rotation of a frame about the tree's vertical axis.
Frame rotate_about_vertical(const Frame& f, float a);

// §4.3 orientation of a child stem or leaf: turn about the parent's axis by nRotate (alternating
// when negative; `rotate_deg` and `alternate` carry the running state along the parent) or, for a
// fan, by `fan_deg` about the parent's y axis; then tilt down by nDownAngle at `ratio` along it.
Frame orient_child(const Frame& parent_frame, const WeberPennLevel& lp, Reading reading, float ratio, float u_down,
                   float u_rot, bool fan, float fan_deg, float& rotate_deg, int& alternate);

// The frame with its z axis normalised and x made orthogonal to it.
Frame orthonormalized(const Frame& f);

// Turns frame f so that its z axis becomes `to` (unit), by the shortest rotation.
Frame turn_to(const Frame& f, const Vec3& to);

// §4.8: turns f up by `angle_rad` (down when negative) about the horizontal axis across its z axis.
Frame turn_up(const Frame& f, float angle_rad);

// A stem on flat ground: a segment of length `seg_len` from `start` whose end would come closer to
// the ground than `clearance` (its radius there) is turned up, keeping its heading, just enough to
// stay at that height; the stem then goes on from the turned frame, as if grown along the ground.
Frame keep_above_ground(const Frame& f, const Vec3& start, float seg_len, float clearance);

}  // namespace sylva::wp
