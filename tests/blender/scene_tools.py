# What the exporter test's scene scripts (make_*.py, run inside Blender) share.
import bpy
from mathutils import Vector


def add_camera(scene, lens, location, target, width, height):
    """The scene's camera: `lens` mm on a 36 mm sensor at `location`, aimed at `target`
    (Blender's z-up frame) with +z up in the image, rendering width x height pixels.
    Returns the camera's data, for settings such as depth of field."""
    camera = bpy.data.cameras.new("Camera")
    camera.lens = lens
    camera.sensor_width = 36
    camera.sensor_fit = "AUTO"
    camera_object = bpy.data.objects.new("Camera", camera)
    camera_object.location = location
    direction = Vector(target) - camera_object.location
    camera_object.rotation_euler = direction.to_track_quat("-Z", "Y").to_euler()
    scene.collection.objects.link(camera_object)
    scene.camera = camera_object
    scene.render.resolution_x = width
    scene.render.resolution_y = height
    scene.render.resolution_percentage = 100
    return camera
