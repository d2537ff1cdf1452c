#pragma once
// Geometry of rigid objects against points: inside tests, entry faces, penetration.
#include "core/physics/model.h"
#include "core/physics/state.h"

namespace enact::physics {

// is x inside any box of the object (planes: below the surface)?
bool inside(const Model& model, const Object& object, const Vec3& x);

// update one contact pair's memory for a point that moved from x_prev to x; returns the
// penetration depth along the remembered face (0 when not in contact)
double update_contact(const Model& model, const Object& object, const Vec3& x_prev, const Vec3& x,
                      ContactState& contact);

// can a point be inside both objects at once? Conservative: false only when their volumes
// are disjoint (a box on a plane, boxes apart); used to sum the stiffness that can act at once
bool objects_overlap(const Model& model, const Object& a, const Object& b);

}  // namespace enact::physics
