"""BELLHOP3D's Nx2D route: measured against the per-radial 2-D runs and kept out of the build
(docs/nx2d.md). It uses BELLHOP's package and the builders, and nothing uses it."""
