"""Composing trees (layer 3 of mjcf): attaching and detaching models, default classes,
settings, copies, finding elements, generated names, and how composed models are written
(`composition`, `keyframes`, `sharing`). Imports only the layers below; see
docs/architecture.md."""
