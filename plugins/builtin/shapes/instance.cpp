/*
 * instance — a shape group placed by `toWorld` (any affine transform: rotation,
 * non-uniform scale, mirroring). Rays are carried into the group's space, so an instance
 * costs a 56-byte record in the instance BVH, never a copy of the geometry; normals
 * follow the inverse transpose and t stays in world units. Its one child is a <ref> to
 * a shape group declared before it.
 *
 * Parameters:
 *   toWorld  transform  identity  group space -> world space
 *
 *   <mesh type="shapegroup" id="pair">
 *       <mesh type="shapegroup" id="ball">
 *           <mesh type="sphere"> <float name="radius" value="0.5"/> </mesh>
 *       </mesh>
 *       <mesh type="instance"> <ref id="ball"/> </mesh>
 *       <mesh type="instance">
 *           <ref id="ball"/>
 *           <transform name="toWorld">
 *               <scale value="1, 2, 1"/> <translate value="1.5, 0, 0"/>
 *           </transform>
 *       </mesh>
 *   </mesh>
 */
#include <nori/instance.h>

namespace nori {
namespace {

NORI_REGISTER_CLASS(Instance, "instance");

} // namespace
} // namespace nori
