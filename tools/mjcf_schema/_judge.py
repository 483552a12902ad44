"""Run one case of the differential check through MuJoCo and through mjcf.

MuJoCo's verdict is its XML reader's (``MjSpec.from_string``): what mjcf must
accept is what the reader accepts, since mjcf, like the reader, leaves to the
compiler what depends on the whole model. When both accept, the model MuJoCo
compiles from the case's text is compared field by field with the one it
compiles from mjcf's ``to_xml_string()``, after parsing and after making the
same change through the API (both compile, or both fail with the same error).
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import mujoco
import numpy as np

import mjcf
from tools.mjcf_schema._cases import FILES, Case, Edit

# Fields that say where files were found or where the model is in memory, not what it is.
_PATH_FIELDS = frozenset({"paths", "name_pathadr", "npaths", "nbuffer", "ptr"})


@dataclass(frozen=True)
class Explanation:
    """A kind of disagreement that is understood: why mjcf differs there."""

    name: str
    reason: str
    stricter: bool  # mjcf refuses what MuJoCo takes (listed in the README)


EXPLANATIONS = {
    e.name: e
    for e in (
        Explanation(
            "name separator",
            "'/' in a name is refused when parsing (unless escape_separators=True): it "
            "separates the names of attached models ('arm/shoulder')",
            stricter=True,
        ),
        Explanation(
            "dangling reference",
            "a reference to an element that does not exist is refused when parsing (as "
            "dm_control does; resolve_references=False defers it); MuJoCo refuses it when "
            "compiling",
            stricter=True,
        ),
        Explanation(
            "missing file",
            "writing a model reads every file it names (models carry their assets), so a "
            "missing file is an error even where MuJoCo would not open it",
            stricter=True,
        ),
        Explanation(
            "count refused when compiling",
            "a count of numbers that is not a multiple MuJoCo's compiler needs (a mesh's "
            "vertex: 3 per vertex) is refused when set; MuJoCo's reader takes it, and its "
            "compiler refuses it, or ignores it where it does not use it (a flex's "
            "nodecoord without nodes)",
            stricter=True,
        ),
        Explanation(
            "duplicate name",
            "a name used twice in one namespace is refused when parsing and editing (a name "
            "finds, binds and attaches one element); MuJoCo refuses it when compiling, but "
            "for flexes, whose names it does not check",
            stricter=True,
        ),
        Explanation(
            "second free joint",
            "a body's second <freejoint> is refused when parsing and adding (a body has one, "
            "None until added, as in dm_control); MuJoCo's reader takes it and its compiler "
            "refuses it (more than 6 dofs in a body)",
            stricter=True,
        ),
        Explanation(
            "unknown object type",
            "a <user> sensor's objtype must name a kind of object; MuJoCo reads any other "
            "text ('true', a typo) as an unknown type and ignores objname",
            stricter=True,
        ),
        Explanation(
            "not numbers",
            "an attribute of numbers holds numbers a double can hold; MuJoCo's reader "
            "leaves a mesh's params and a height field's elevation unread until it uses "
            "them, and takes any text there ('abc', '1e309')",
            stricter=True,
        ),
        Explanation(
            "ignored by MuJoCo",
            "an element MuJoCo's reader takes where it means nothing and leaves out of the "
            "model (<body>, <frame> or <replicate> directly in <mujoco>) is refused, so that "
            "nothing a model says is silently dropped",
            stricter=True,
        ),
        Explanation(
            "crashes MuJoCo",
            "what MuJoCo 4.0.0 crashes or hangs on is refused (mjcf/schema/_refusals.py): a "
            "<plugin> without plugin or instance (which MuJoCo's compile refuses elsewhere), "
            "a file mesh with a <plugin>, 'frame' as an object type, a gear or armature that "
            "is not finite",
            stricter=True,
        ),
        Explanation(
            "empty reference",
            "a reference MuJoCo looks up even when it is empty, where '' finds the first "
            "unnamed element (a <pair>'s geoms, an <exclude>'s bodies, an equality's first "
            "object, a tendon's path), must name its element: mjcf names every element it "
            "writes, so '' would find none",
            stricter=True,
        ),
        Explanation(
            "checked later",
            "through the API, a reference may name an element added later and a required "
            "attribute may be set later: required attributes are checked when the model is "
            "written, names when MuJoCo compiles it, and both fail then",
            stricter=False,
        ),
        Explanation(
            "beyond memory",
            "a size so large that MuJoCo's reader fails to allocate what it makes (a "
            "flexcomp of 2147483647 points) is left to MuJoCo, as the machine's memory "
            "decides it; MuJoCo fails on mjcf's model the same way",
            stricter=False,
        ),
        Explanation(
            "generated name",
            "an element written without a name gets the one mjcf gives it, as dm_control "
            "names it ('//unnamed_material_0'), so a material, texture or height field left "
            "unnamed (or named '') compiles, where MuJoCo refuses its empty name",
            stricter=False,
        ),
        Explanation(
            "not a range",
            "values MuJoCo accepts that are not one range (a mesh's maxhullvert: -1 or more "
            "than 3; a quaternion: anything but zeros) are left to MuJoCo's reader",
            stricter=False,
        ),
        Explanation(
            "meaning in context",
            "MuJoCo's reader checks what a value means together with other values, "
            "attributes, files or elements (a flexcomp's spacing against its radius, the "
            "points its count makes against its elements, a texture's gridlayout against "
            "its gridsize, the two axes of an xyaxes, the bodies of an attached model's "
            "file); mjcf leaves these to MuJoCo's compile, where they fail the same way",
            stricter=False,
        ),
    )
}

# What MuJoCo's reader says when it refuses a value for what it means together with
# other attributes, files or elements ("meaning in context").
_CONTEXT = re.compile(
    "|".join(
        (
            r"Spacing must be larger than geometry size",
            r"two texture coordinates per vertex expected",
            r"Element size must be a multiple of dim\+1",
            r"Pin grid (range )?number (of )?must be multiple of",
            r"pinid out of range",
            r"pinrange out of range",
            r"No elements were created in",
            r"Count too small",
            r"Point and element required",
            r"File is required",
            r"yaxis too small",
            r"gridlayout length must match gridsize",
            r"World body cannot have joints",
            r"could not find (body|frame) '.*' in model asset",
            r"could not find model",
            r"could not parse model file",
            r"plugin .*not found",
            r"DC motor: ",
            r"repeated name '.*' in",
            r"World body cannot have",
            r"objtype is specified but objname is not",
            r"element \d+ has point id \d+, number of points is",
            r"cross\(xaxis, yaxis\) too small",
        )
    )
)
_UNKNOWN = "Caught an unknown exception!"
_HUGE = re.compile(r"\b[1-9]\d{9,}\b")  # a number of ten digits or more
_EMPTY_NAME = re.compile(r"Error: empty name in ")
_NOT_A_RANGE = re.compile(r"maxhullvert must be larger than|zero quaternion")


@dataclass(frozen=True)
class Finding:
    """A disagreement between MuJoCo and mjcf on one case; `explained` names the
    `EXPLANATIONS` entry that accounts for it, if one does."""

    case: Case
    stage: str  # 'parse', 'edit', 'baseline', 'write', 'compile'
    mujoco: str  # what MuJoCo did ('accepted' or its error)
    mjcf: str  # what mjcf did
    explained: str | None = None

    def line(self) -> str:
        """One line for a report."""
        why = f" ({self.explained})" if self.explained else ""
        return f"[{self.stage}]{why} {self.case.subject}: MuJoCo {self.mujoco}; mjcf {self.mjcf}"


def _first_line(error: BaseException | str) -> str:
    text = str(error).strip().split("\n")[0]
    return re.sub(r"\s+", " ", text)[:300]


# Whether MuJoCo's bindings have raised something other than their ValueError in this
# process: MuJoCo 4.0.0's may then hang on a later warning, so a worker that saw it is
# replaced (see _workers).
_bindings_failed = False


def bindings_failed() -> bool:
    """Whether MuJoCo's bindings failed in this process (see `_bindings_failed`)."""
    return _bindings_failed


def _failed(error: Exception) -> None:
    global _bindings_failed
    if not isinstance(error, ValueError):
        _bindings_failed = True


def reader_error(document: str) -> str | None:
    """MuJoCo's reader's error for ``document``, or None if it reads it."""
    try:
        mujoco.MjSpec.from_string(document, include=FILES)
    except Exception as error:  # the reader raises ValueError, sometimes others
        _failed(error)
        return _first_line(error)
    return None


def compiled(document: str, assets: dict[str, bytes]) -> mujoco.MjModel | str:
    """The model MuJoCo compiles from ``document``, or its error without the line
    and element numbers (which differ between equivalent documents)."""
    try:
        return mujoco.MjModel.from_xml_string(document, assets)
    except Exception as error:
        _failed(error)
        text = str(error).split("\nElement")[0]
        text = re.sub(r",? ?line \d+|id \d+|(?<=probe)\d+_", "", text)
        return re.sub(r"\s+", " ", text).strip()


def model_differences(a: mujoco.MjModel, b: mujoco.MjModel) -> list[str]:
    """The names of the sizes and arrays of MjModel (and its options) that differ; the
    names of objects are compared as lists per kind of object, the names mjcf gives
    elements nobody named (as dm_control does, '//unnamed_camera_1') counting as none."""
    theirs = _names(b)
    differences = [f"names of {kind}" for kind, names in _names(a).items() if theirs[kind] != names]
    for owner, prefix in ((a, ""), (a.opt, "opt."), (a.vis, "vis."), (a.stat, "stat.")):
        other = b if owner is a else getattr(b, prefix[:-1])
        differences += _object_differences(owner, other, prefix)
    return differences


def _names(model: mujoco.MjModel) -> dict[str, list[bytes]]:
    """{'cam': [name of camera 0, ...], ...}, generated names as b''."""
    buffer = model.names
    found = {}
    for field in _fields(type(model)):
        if field.startswith("name_") and field.endswith("adr"):
            names = [buffer[start : buffer.index(b"\0", start)] for start in getattr(model, field)]
            found[field[5:-3]] = [b"" if _GENERATED.fullmatch(n) else n for n in names]
    return found


def _fields(kind: type) -> tuple[str, ...]:
    """The public fields of a type of MuJoCo's structs, but where files are."""
    found = _FIELDS.get(kind)
    if found is None:
        found = _FIELDS[kind] = tuple(
            name
            for name in dir(kind)
            if not name.startswith("_")
            and name not in _PATH_FIELDS
            and not name.endswith("_pathadr")
        )
    return found


_FIELDS: dict[type, tuple[str, ...]] = {}


_GENERATED = re.compile(rb"//unnamed_[a-z_]+_\d+")


def _object_differences(a: object, b: object, prefix: str) -> list[str]:
    differences = []
    for name in _fields(type(a)):
        if name in ("names", "names_map", "nnames", "nnames_map") or (
            name.startswith("name_") and name.endswith("adr")
        ):
            continue
        first = getattr(a, name)
        if isinstance(first, type) or callable(first) or name in ("opt", "vis", "stat"):
            continue
        second = getattr(b, name)
        if isinstance(first, np.ndarray):
            if first.shape != second.shape or not np.array_equal(first, second, equal_nan=True):
                differences.append(prefix + name)
        elif isinstance(first, bool | int | float | bytes | str):
            if first != second and not (first != first and second != second):
                differences.append(prefix + name)
        elif type(first).__module__.startswith("mujoco"):  # a struct of MjVisual
            differences += _object_differences(first, second, f"{prefix}{name}.")
    return differences


def _explain_refusal(error: str, case: Case) -> str | None:
    if _CONTEXT.search(error):
        return "meaning in context"
    # MuJoCo 4.0.0's bindings report a failed allocation so (std::bad_alloc).
    if error == _UNKNOWN and _HUGE.search(case.subject):
        return "beyond memory"
    if _NOT_A_RANGE.search(error):
        return "not a range"
    return None


def _ignored(case: Case) -> bool:
    """Whether MuJoCo compiles a case's document into the model it compiles without
    what the case adds (a child, an attribute)."""
    if case.baseline is None:
        return False
    with_child, without = compiled(case.document, FILES), compiled(case.baseline, FILES)
    if isinstance(with_child, str) or isinstance(without, str):
        return False
    return not model_differences(with_child, without)


def _locate(root: mjcf.RootElement, path: tuple[str, ...]) -> mjcf.Element:
    element: mjcf.Element = root
    for tag in path:
        matches = [c for c in element._children if c.tag == tag]
        element = matches[-1]
    return element


def _apply(root: mjcf.RootElement, edit: Edit) -> None:
    element = _locate(root, edit.path)
    if edit.child is not None:
        element.add(edit.child, **dict(edit.child_attributes))
    else:
        element.set_attributes(**{str(edit.attribute): edit.text})


class Judge:
    """Runs cases; collects findings."""

    def __init__(self) -> None:
        self.findings: list[Finding] = []
        self.counts = {"cases": 0, "accepted": 0, "compiled": 0}

    def run(self, case: Case) -> None:
        """Judge one case: acceptance by parse and by edit, then the compiled models."""
        self.counts["cases"] += 1
        expected = reader_error(case.document)
        verdict = "accepted" if expected is None else f"refuses ({expected})"
        root, error = self._parse(case.document)
        if (root is None) != (expected is not None):
            why = self._explain_parse(case, expected, error)
            self.findings.append(Finding(case, "parse", verdict, error or "accepts", why))
            return
        reference = None
        if root is not None:
            self.counts["accepted"] += 1
            reference = compiled(case.document, FILES)
            self.counts["compiled"] += not isinstance(reference, str)
            self._compare(case, "compile", reference, root)
        if case.edit is None or case.baseline is None or reader_error(case.baseline):
            return
        base, error = self._parse(case.baseline)
        if base is None:
            why = self._explain_parse(case, None, error)
            refusal = error or "refuses"
            self.findings.append(Finding(case, "baseline", "accepts the baseline", refusal, why))
            return
        try:
            _apply(base, case.edit)
        except mjcf.Error as caught:
            if expected is None:
                why = self._explain_parse(case, None, _first_line(caught))
                self.findings.append(Finding(case, "edit", verdict, _first_line(caught), why))
            return
        except Exception as caught:  # a crash is always a finding
            self.findings.append(Finding(case, "edit", verdict, f"crashes: {caught!r}"))
            return
        if expected is not None:
            why = _explain_refusal(expected, case)
            try:
                text, assets = base.to_xml_string(), base.get_assets()
            except mjcf.Error as caught:
                why = "checked later"
                verdict += f"; mjcf refuses to write it ({_first_line(caught)})"
            else:
                if why is None and isinstance(compiled(text, assets), str):
                    why = "checked later"  # e.g. an unknown class name, when compiling
            self.findings.append(Finding(case, "edit", verdict, "accepts", why))
            return
        self._compare(case, "edit-compile", reference, base)

    def _explain_parse(self, case: Case, expected: str | None, error: str | None) -> str | None:
        if expected is not None:
            return _explain_refusal(expected, case)
        error = error or ""
        if "the separator of attached models" in error or "separates the names" in error:
            return "name separator"
        if "<user>: 'objtype' takes one of" in error:
            return "unknown object type"
        if re.search(r"<(mesh|hfield)>: '(params|elevation)' takes numbers", error):
            return "not numbers"
        if "already used by another flex" in error:
            return "duplicate name"
        if "MuJoCo 4.0.0 crashes on it" in error or "compile never ends" in error:
            return "crashes MuJoCo"
        if "which MuJoCo reads as the first" in error or "<pair> requires the attribute" in error:
            return "empty reference"
        if case.kind == "child" and "cannot have a <" in error and _ignored(case):
            return "ignored by MuJoCo"
        kinds = (
            ("dangling references", "dangling reference"),
            ("already used by", "duplicate name"),
            ("may have only one <freejoint>", "second free joint"),
            ("numbers, a multiple of", "count refused when compiling"),
        )
        for text, name in kinds:
            if text in error and isinstance(compiled(case.document, FILES), str):
                return name
        if "numbers, a multiple of" in error and case.kind == "value" and _ignored(case):
            return "count refused when compiling"
        return None

    def _parse(self, document: str) -> tuple[mjcf.RootElement | None, str | None]:
        try:
            return mjcf.from_xml_string(document, assets=FILES), None
        except mjcf.Error as error:
            return None, f"refuses ({_first_line(error)})"
        except Exception as error:
            return None, f"crashes ({error!r})"

    def _compare(self, case: Case, stage: str, reference: object, root: mjcf.RootElement) -> None:
        try:
            text, assets = root.to_xml_string(), root.get_assets()
        except Exception as error:
            why = "missing file" if isinstance(error, mjcf.AssetError) else None
            got = f"cannot write: {_first_line(error)}"
            self.findings.append(Finding(case, stage, "compiles", got, why))
            return
        ours = compiled(text, assets)
        if isinstance(reference, str) or isinstance(ours, str):
            # Both failing agrees: which error comes first depends on element order.
            if isinstance(reference, str) != isinstance(ours, str):
                shown = reference if isinstance(reference, str) else "compiles"
                got = ours if isinstance(ours, str) else "compiles"
                why = "generated name" if _EMPTY_NAME.match(shown) else None
                self.findings.append(Finding(case, stage, shown, got, why))
            return
        differences = model_differences(reference, ours)
        if differences:
            self.findings.append(
                Finding(
                    case, stage, "compiles", "compiles differently: " + ", ".join(differences[:8])
                )
            )
