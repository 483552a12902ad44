"""Reading and writing MJCF text (layer 4 of mjcf): the reader (`parser`, with `xsd`,
`indexer` and `default_sections`), the writer (`serializer`), `export`, and `archives`
(zip archives unpacked within limits). Imports only the layers below; see
docs/architecture.md."""
