"""dm_control's `mjcf.parser` module path: the readers `from_path`, `from_xml_string`,
`from_file` and `from_zip`. Defined in `mjcf.io.parser` and `mjcf.io.export`."""

from mjcf.io.export import from_zip
from mjcf.io.parser import from_file, from_path, from_xml_string

__all__ = ["from_file", "from_path", "from_xml_string", "from_zip"]
