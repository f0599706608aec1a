// The shapes of pbrt-v4 that have no plugin of ours of the same form, as triangle meshes:
// partial quadrics (pbrt-v4's zmin, zmax, phimax, innerradius) tessellated with pbrt-v4's
// (u, v) parameterisation, bilinear patches split into triangles, and Loop subdivision
// surfaces subdivided to their level and pushed to the limit surface.
#pragma once

#include <nori/meshdata.h>

#include <vector>

namespace nori::pbrt {

/// The sphere of pbrt-v4's `sphere` (PBR 4th ed. §6.2): radius r, cut at z ∈ [zMin, zMax]
/// and φ ≤ φMax (radians); u = φ/φMax, v = (θ − θ(zMin))/(θ(zMax) − θ(zMin)), normals
/// outward. `segments` quads around a full turn.
MeshData tessellateSphere(float radius, float zMin, float zMax, float phiMax, int segments);
/// pbrt-v4's `disk` (§6.3 of the 4th ed.): at z = height, radii [innerRadius, radius], φ ≤
/// φMax; u = φ/φMax, v = (radius − r)/(radius − innerRadius), normals along +z.
MeshData tessellateDisk(float height, float radius, float innerRadius, float phiMax, int segments);
/// pbrt-v4's `cylinder` (§6.3): radius r about the z axis from zMin to zMax, φ ≤ φMax;
/// u = φ/φMax, v = (z − zMin)/(zMax − zMin), normals outward.
MeshData tessellateCylinder(float radius, float zMin, float zMax, float phiMax, int segments);

/// pbrt-v4's `bilinearmesh`: each patch's four vertices (p00, p10, p01, p11) in `indices`
/// as two triangles (exact for planar patches), normals and uvs carried over.
MeshData bilinearPatchesToTriangles(MeshData patches, const std::vector<int> &indices);

/// Loop subdivision (Loop 1987; PBR 3rd ed. §3.8): `levels` steps of the rules for even
/// and odd vertices (Warren's β for interior vertices, the cubic B-spline rule on
/// boundaries), then every vertex moved to its limit position. Normals: the area-weighted
/// average of the face normals around each vertex of the finest mesh (pbrt derives them
/// from the limit surface's tangents; the two agree more closely with every level).
MeshData loopSubdivide(MeshData mesh, int levels);

} // namespace nori::pbrt
