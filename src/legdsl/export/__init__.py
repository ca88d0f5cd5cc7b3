"""Files for other programs and for people: MJCF and URDF, glTF, the HTML player and video."""
