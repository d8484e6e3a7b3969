"""The pieces of scenes/assets/make_assets.py, by what they make: textures, skyboxes,
environments, the OBJ models of each example scene and the GLB of the pbr scene, with the
helpers they share (colour, noise, images, geometry, OBJ/MTL writing)."""
