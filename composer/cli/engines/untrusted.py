"""Reading a policy file from a stranger, for every engine's plain reader (no --trust-policy):
each part is checked to be what `composer train` writes before a library sees it; a malformed
or hostile file raises one PolicyError naming the file, the part and what was expected.

    unpacker = untrusted.unpacker()                     # mjcf.archives' limits in force
    with untrusted.archive(file, file) as zipped:       # PolicyError for what is no zip
        text = untrusted.entry(unpacker, zipped, 'data', file)   # within the limits
    data = untrusted.json_data(text, f'{file}: data')     # plain JSON, MAX_DEPTH deep
    with untrusted.at_most(torch, untrusted.capacity(numbers), file):
        network = build(settings)                       # refused as soon as it grows past
"""

from __future__ import annotations

import contextlib
import io
import json
import math
import zipfile
from collections.abc import Iterator
from pathlib import Path
from typing import IO, Any

import numpy as np

import mjcf
from composer.cli.errors import PolicyError
from mjcf import archives

# How deep a policy's JSON may nest: composer's and the libraries' settings nest 4 levels.
MAX_DEPTH = 32
# How large a shape may be: the elements of one observation or action.
MAX_ELEMENTS = 1 << 28
RAISE_WITH = (
    f"--unpack-limit and --unpack-ratio (or the environment variables "
    f"{archives.SIZE_VARIABLE}, {archives.RATIO_VARIABLE})"
)


def unpacker() -> archives.Unpacker:
    """An Unpacker for one policy, with the limits in force: every archive of a policy (a
    stable-baselines3 .zip, the torch file inside it, numpy's .npz) is unpacked through one
    `mjcf.archives.Unpacker`, within its limits, which `--unpack-limit`, `--unpack-ratio` or
    the environment variables MJCF_UNPACK_LIMIT, MJCF_UNPACK_RATIO raise (`mjcf.archives`,
    the one owner of that rule)."""
    try:
        return archives.Unpacker(raise_with=RAISE_WITH)
    except mjcf.UnpackLimitError as e:
        raise PolicyError(str(e)) from None


def archive(source: Path | IO[bytes], where: object) -> zipfile.ZipFile:
    """The zip archive `source` (a file, or bytes in a BytesIO); raises PolicyError naming
    `where` for one that cannot be read as a zip (whatever zipfile raises for it)."""
    try:
        return archives.open_archive(source, where)
    except mjcf.ParseError as e:
        raise PolicyError(str(e)) from None


def entry(unpacker: archives.Unpacker, archive: zipfile.ZipFile, name: str, file: Path) -> bytes:
    """The unpacked entry `name` of `archive` (the policy `file`); raises PolicyError
    when it is missing, corrupt, or past the unpacker's limits."""
    try:
        return unpacker.read(archive, name, file)
    except KeyError:
        message = f"{file} has no {name!r}: not a policy written by `composer train`"
        raise PolicyError(message) from None
    except mjcf.ParseError as e:  # mjcf.UnpackLimitError too
        raise PolicyError(str(e)) from None


def inner_archive(unpacker: archives.Unpacker, data: bytes, where: str) -> None:
    """If `data` is a zip (torch's file format is one), unpack each of its entries within
    the unpacker's limits, which its reader then allocates no more than; raises
    PolicyError."""
    if not zipfile.is_zipfile(io.BytesIO(data)):
        return
    with archive(io.BytesIO(data), where) as inner:
        for info in inner.infolist():
            try:
                unpacker.read(inner, info, where)
            except mjcf.ParseError as e:  # mjcf.UnpackLimitError too
                raise PolicyError(str(e)) from None


def json_data(text: bytes | str, where: str) -> Any:
    """`text` read as JSON nested at most MAX_DEPTH levels; raises PolicyError naming
    `where` otherwise."""
    try:
        value = json.loads(text)
    except (ValueError, RecursionError) as e:  # RecursionError: nested a thousand levels
        reason = "nested too deeply" if isinstance(e, RecursionError) else str(e)
        raise PolicyError(f"{where} is not JSON: {reason}") from None
    stack = [(value, 1)]
    while stack:
        node, depth = stack.pop()
        if depth > MAX_DEPTH:
            raise PolicyError(f"{where} nests its JSON deeper than {MAX_DEPTH} levels")
        if isinstance(node, dict):
            stack.extend((child, depth + 1) for child in node.values())
        elif isinstance(node, list):
            stack.extend((child, depth + 1) for child in node)
    return value


def mapping(value: Any, where: str) -> dict[str, Any]:
    """`value` if it is a JSON object; raises PolicyError naming `where` otherwise."""
    if not isinstance(value, dict):
        raise PolicyError(f"{where} must be a JSON object, got {_shown(value)}")
    return value


def number(value: Any, where: str, minimum: float = -math.inf) -> float:
    """`value` as a finite float of at least `minimum`; raises PolicyError otherwise."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise PolicyError(f"{where} must be a number, got {_shown(value)}")
    if not math.isfinite(value) or value < minimum:
        raise PolicyError(f"{where} must be a finite number of at least {minimum:g}, got {value}")
    return float(value)


def shape(value: Any, where: str) -> tuple[int, ...]:
    """`value` as an array shape: a list of positive integers of at most MAX_ELEMENTS
    elements in all; raises PolicyError otherwise."""
    if not isinstance(value, list) or not all(
        isinstance(n, int) and not isinstance(n, bool) and n > 0 for n in value
    ):
        raise PolicyError(f"{where} must be a list of positive integers, got {_shown(value)}")
    if math.prod(value) > MAX_ELEMENTS:
        raise PolicyError(f"{where} has more than {MAX_ELEMENTS:,} elements: {value}")
    return tuple(value)


def numbers(value: Any, where: str, size: tuple[int, ...]) -> np.ndarray:
    """`value` as a float64 array of shape `size`, every element finite; raises
    PolicyError otherwise."""
    try:
        array = np.array(value, dtype=np.float64)
    except (ValueError, TypeError, OverflowError, RecursionError):
        array = None
    if array is None or array.shape != size or not np.all(np.isfinite(array)):
        raise PolicyError(f"{where} must be {_count(size)} finite numbers, got {_shown(value)}")
    return array


def npz_arrays(path: Path, unpacker: archives.Unpacker) -> dict[str, np.ndarray]:
    """The arrays of numpy's .npz file `path`, each unpacked within the unpacker's limits,
    of numbers (no objects, so no pickle) and holding the elements its header declares;
    raises PolicyError otherwise."""
    arrays = {}
    with archive(path, path) as npz:
        for info in npz.infolist():
            name = info.filename.removesuffix(".npy")
            arrays[name] = _array(entry(unpacker, npz, info.filename, path), f"{path}: {name!r}")
    return arrays


def _array(data: bytes, where: str) -> np.ndarray:
    """The numbers of one .npy file's bytes `data` (see `npz_arrays`)."""
    stream = io.BytesIO(data)
    try:
        version = np.lib.format.read_magic(stream)
        read_header = {(1, 0): np.lib.format.read_array_header_1_0,
                       (2, 0): np.lib.format.read_array_header_2_0}.get(version)  # fmt: skip
        if read_header is None:
            raise ValueError(f"version {version} of the .npy format")
        size, fortran, dtype = read_header(stream)
    except (ValueError, TypeError, SyntaxError) as e:
        raise PolicyError(f"{where} is not an array numpy wrote: {e}") from None
    if dtype.hasobject or dtype.kind not in "biuf":
        raise PolicyError(f"{where} holds {dtype} values, not numbers")
    count = math.prod(size)
    if count * dtype.itemsize != len(data) - stream.tell():
        raise PolicyError(
            f"{where} declares {_count(size)} {dtype} values, but holds "
            f"{len(data) - stream.tell():,} bytes"
        )
    array = np.frombuffer(data, dtype, count, stream.tell())
    return array.reshape(size, order="F" if fortran else "C").copy()


@contextlib.contextmanager
def at_most(torch: Any, capacity: int, source: object) -> Iterator[None]:
    """Within `with`: a network of `torch` (the module, which only engines import) whose
    parameters and buffers pass `capacity` numbers in all is refused with PolicyError as
    each is made, before it is filled: a stranger's settings (`source`'s) spend no more
    memory than the network its weights fill (give their count, with room for what the
    library builds and drops)."""
    made = [0]

    def count(module: Any, name: str, tensor: Any) -> None:
        made[0] += 0 if tensor is None else int(tensor.numel())
        if made[0] > capacity:
            raise PolicyError(
                f"{source}: its settings make a network of more than {capacity:,} numbers, "
                "far more than its weights fill"
            )

    hooks = (
        torch.nn.modules.module.register_module_parameter_registration_hook(count),
        torch.nn.modules.module.register_module_buffer_registration_hook(count),
    )
    try:
        yield
    finally:
        for hook in hooks:
            hook.remove()


def capacity(numbers: int) -> int:
    """The numbers `at_most` lets a network of weights holding `numbers` numbers make: twice
    them and a million more, room for what a library builds and then drops (RLlib builds a
    module's value head before leaving it out of an inference-only one)."""
    return 2 * numbers + (1 << 20)


def _count(size: tuple[int, ...]) -> str:
    return f"shape {size}" if len(size) != 1 else f"{size[0]}"


def _shown(value: Any) -> str:
    """`value` in a message: its JSON, cut short."""
    try:
        text = json.dumps(value)
    except (ValueError, TypeError, RecursionError):
        text = type(value).__name__
    return text if len(text) <= 60 else text[:57] + "..."
