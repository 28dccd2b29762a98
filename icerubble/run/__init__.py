"""A punch-through run: scene presets and their cached piles and meshes, the
scene built from a mesh, the run itself (settle, load, record), its
checkpoints and progress, its identity, and one line of a study table."""
