#pragma once
// Geometry of rigid objects against points: inside tests, entry faces, penetration.
#include "core/physics/model.h"
#include "core/physics/state.h"

namespace enact::physics {

// update one contact pair for a point that moved from x_prev to x; returns the penetration
// depth below the face that pushes (0 when not in contact). skin_m: how far below another
// face a point may be to ride over an edge onto it (ContactPair::edge_skin_m). hold: use the
// contact's held face while it holds (false: the full face test, the reference)
double update_contact(const Model& model, const Object& object, const Vec3& x_prev, const Vec3& x, double skin_m,
                      ContactState& contact, bool hold = true);

// can no point within radius_m of centre_m be inside the object? (a plane: the sphere is
// above it; boxes: the sphere is outside every box along one of its axes)
bool apart(const Model& model, const Object& object, const Vec3& centre_m, double radius_m);

// can a point be inside both objects at once? Conservative: false only when their volumes
// are disjoint (a box on a plane, boxes apart); used to sum the stiffness that can act at once
bool objects_overlap(const Model& model, const Object& a, const Object& b);

}  // namespace enact::physics
