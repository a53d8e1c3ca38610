// The common subset of GLSL and C++ (with glm) in which the physics both tracers share is
// written once (emitter.h: the sources' emission; material.h: the reflector's finish), and
// the orthonormal frame about a direction that both need. GLSL compiles the text in float,
// C++ in double (namespace fird::gpu::emission).
//
// The subset: value parameters only (no out), structs filled member by member, vector
// constructors and +, -, * on vectors, the math functions named below.
#ifndef FIRD_FRAME_H
#define FIRD_FRAME_H

#ifdef __cplusplus
#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "fird_shared.h"

namespace fird::gpu::emission {
using real_t = double;
using vec2 = glm::dvec2;
using vec3 = glm::dvec3;
using vec4 = glm::dvec4;
using glm::cross;
using glm::dot;
using glm::normalize;
using std::abs;
using std::cos;
using std::log;
using std::max;
using std::min;
using std::pow;
using std::sin;
using std::sqrt;
#define FIRD_SHARED_INLINE inline
#else
#define real_t float
#define FIRD_SHARED_INLINE
#endif

const real_t kSharedPi = 3.14159265358979323846;

// Two unit vectors completing n to a right-handed orthonormal frame
// (Duff et al., "Building an orthonormal basis, revisited", 2017).
struct Basis {
    vec3 t;
    vec3 b;
};
FIRD_SHARED_INLINE Basis basis_about(vec3 n) {
    const real_t s = n.z >= 0.0 ? 1.0 : -1.0;
    const real_t a = -1.0 / (s + n.z);
    const real_t c = n.x * n.y * a;
    Basis f;
    f.t = vec3(1.0 + s * n.x * n.x * a, s * c, -s * n.x);
    f.b = vec3(c, s + n.y * n.y * a, -n.y);
    return f;
}

#ifdef __cplusplus
} // namespace fird::gpu::emission
#endif
#endif
