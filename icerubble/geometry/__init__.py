"""Geometry of a ridge: phase-1 blocks (pile), their contacts resolved into bond
lines (contact_resolution), the gmsh mesh (meshing) and its bond points."""
