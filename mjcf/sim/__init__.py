"""Compiling and simulating (layer 5 of mjcf): `budget` (what a model may ask MuJoCo to
build), `compiler`, `Physics`, bindings, named access, rendering. Imports any layer below;
see docs/architecture.md."""
