"""The element tree (layer 2 of mjcf): `Element`, `RootElement`, their names and
references, and the assets their file attributes hold. Imports only `mjcf.schema` and
`mjcf.errors`; see docs/architecture.md."""
