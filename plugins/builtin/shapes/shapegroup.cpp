/*
 * shapegroup — shapes that render only where instances place them. Declare it with an
 * id, then place it with <mesh type="instance"> and a <ref>. A group holds any shapes
 * (with their tmesh copies), instances of groups declared before it, and nested group
 * declarations; instances nest up to 8 levels. Its shapes have one BVH, built once
 * and shared by every instance. Area lights inside a group are refused (instanced
 * geometry does not emit).
 *
 * No parameters: the group's content is its children.
 *
 *   <mesh type="shapegroup" id="tuft">
 *       <mesh type="obj">
 *           <string name="filename" value="scenes/cbox/meshes/floor.obj"/>
 *           <bsdf type="diffuse"/>
 *       </mesh>
 *       <mesh type="sphere"> <float name="radius" value="0.3"/> </mesh>
 *   </mesh>
 */
#include <nori/instance.h>

namespace nori {
namespace {

NORI_REGISTER_CLASS(ShapeGroup, "shapegroup");

} // namespace
} // namespace nori
