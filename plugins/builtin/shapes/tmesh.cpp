/*
 * tmesh — a copy of the mesh it is nested in (course style, as Blender exporters write
 * particle systems): the parent's geometry placed again by this element's `toWorld`,
 * applied after the parent's own toWorld. Every copy shares the parent's one BVH (a
 * two-level BVH, see include/nori/accel.h) and costs 56 bytes plus its share of the
 * instance tree. A copy takes the parent's BSDF unless it has its own <bsdf>; uvs and
 * normal or bump maps are the parent's. The parent renders too unless it says
 * `visible` = false. A mesh with copies cannot carry an area light (an error).
 *
 * Parameters:
 *   toWorld  transform  identity  where this copy goes, relative to the parent as placed
 *
 *   <mesh type="obj">
 *       <string name="filename" value="scenes/cbox/meshes/left.obj"/>
 *       <boolean name="visible" value="false"/>
 *       <mesh type="tmesh">
 *           <transform name="toWorld"> <translate value="-1, 0, 0"/> </transform>
 *       </mesh>
 *       <mesh type="tmesh">
 *           <transform name="toWorld"> <rotate axis="0, 1, 0" angle="90"/> </transform>
 *           <bsdf type="diffuse"> <color name="albedo" value="0.2, 0.6, 0.2"/> </bsdf>
 *       </mesh>
 *   </mesh>
 */
#include <nori/instance.h>

namespace nori {
namespace {

NORI_REGISTER_CLASS(TMesh, "tmesh");

} // namespace
} // namespace nori
