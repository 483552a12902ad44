"""Compiling and simulating (layer 5 of mjcf): `compiler`, `Physics`, bindings, named
access, rendering. Imports any layer below; see docs/architecture.md."""
