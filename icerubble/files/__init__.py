"""Files: atomic, self-describing HDF5 (h5io), the pile and mesh files with
checked readers, and ParaView fields (vtu). Layouts: docs/pile_and_mesh.md,
docs/results_format.md."""
