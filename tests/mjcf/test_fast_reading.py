"""Reading fast (the XML Schema and the indexer check a document, elements are built when
first used) gives the model reading element by element gives, and raises the errors it
raises, at parse time; the elements not built yet behave as built ones."""

from __future__ import annotations

import copy
import os
import pickle
import subprocess
import sys
from pathlib import Path

import mujoco
import pytest
from lxml import etree

import mjcf
from bench import real_models, synthetic
from mjcf.io import fast_reader, xsd
from tests import dm_control_wheel
from tests.conftest import GYM_ASSETS, MENAGERIE, MUJOCO_TESTDATA, ORIGINAL_MENAGERIE

MODELS = (
    sorted(GYM_ASSETS.glob("*.xml"))
    + sorted(MUJOCO_TESTDATA.glob("*.xml"))
    + sorted(MENAGERIE.glob("*/*.xml"))
    + sorted(ORIGINAL_MENAGERIE.glob("*/*.xml"))  # beside the repository in CI only
)
NAMESPACES = ("body", "joint", "geom", "site", "mesh", "texture", "material", "actuator",
              "sensor", "tendon", "default", "camera", "light", "equality", "exclude")  # fmt: skip


@pytest.fixture(autouse=True)
def fast_from_the_first_document(monkeypatch):
    """Read fast from the first document on (see `fast_reader._ELEMENTS_BEFORE_SCHEMA`)."""
    monkeypatch.setattr(fast_reader, "_ELEMENTS_BEFORE_SCHEMA", 0)


@pytest.fixture
def element_by_element(monkeypatch):
    """Read every document element by element, as before the fast way existed."""
    monkeypatch.setattr(fast_reader, "read", lambda *args: False)


def _read_both(
    path: Path, monkeypatch, text: str | None = None
) -> tuple[mjcf.RootElement, mjcf.RootElement]:
    """The file at `path` (or `text`, read as if it were that file) read fast, then
    element by element; asserts the fast way took it."""

    def read() -> mjcf.RootElement:
        if text is None:
            return mjcf.from_path(path)
        return mjcf.from_xml_string(text, model_dir=str(path.parent))

    taken = []
    read_fast = fast_reader.read
    monkeypatch.setattr(fast_reader, "read", lambda *a: taken.append(read_fast(*a)) or taken[0])
    fast = read()
    monkeypatch.setattr(fast_reader, "read", lambda *args: False)
    slow = read()
    monkeypatch.undo()
    assert taken == [True], "the fast way should read every shipped model"
    return fast, slow


def _assert_same_model(fast: mjcf.RootElement, slow: mjcf.RootElement) -> None:
    for namespace in NAMESPACES:  # names first, with nothing built yet
        named = [e for e in slow.find_all(namespace) if e.identifier is not None]
        found = [fast.find(namespace, e.identifier) for e in named]
        assert [e.path if e else None for e in found] == [e.path for e in named]
    for namespace in NAMESPACES:
        names = [e.full_identifier for e in slow.find_all(namespace)]
        assert [e.full_identifier for e in fast.find_all(namespace)] == names
    assert fast.to_xml_string() == slow.to_xml_string()
    assert fast.is_same_as(slow)


@pytest.mark.parametrize("path", MODELS, ids=lambda p: p.name)
def test_fast_reading_gives_the_element_by_element_model(path: Path, monkeypatch) -> None:
    _assert_same_model(*_read_both(path, monkeypatch))


def _walker(name: str) -> Path:
    try:
        return real_models.walkers()[name]
    except dm_control_wheel.Unavailable as error:
        pytest.skip(f"dm_control's walkers cannot be had: {error}")


@pytest.mark.parametrize("name", sorted(real_models.WALKERS))
def test_dm_control_walkers_read_fast_as_element_by_element(name: str, monkeypatch) -> None:
    """rodent.xml among them, whose top-level <compiler> is repeated."""
    _assert_same_model(*_read_both(_walker(name), monkeypatch))


def _split_sections(path: Path) -> str:
    """The file at `path` with every top-level section in two copies, as MuJoCo merges
    them: the first with the section's attributes and the first half of its children,
    the second, placed after every other section, with its later attributes again and
    the other half."""
    xml_root = etree.parse(str(path)).getroot()
    for section in list(xml_root):
        if not isinstance(section.tag, str) or section.tag == "default":
            continue  # a repeated <default> is read element by element
        children = list(section)
        later = etree.SubElement(xml_root, section.tag)
        for name, value in list(section.attrib.items())[len(section.attrib) // 2 :]:
            later.set(name, value)
        later.extend(children[len(children) // 2 :])
    return etree.tostring(xml_root, encoding="unicode")


@pytest.mark.parametrize("path", MODELS, ids=lambda p: p.name)
def test_repeated_sections_read_fast_as_element_by_element(path: Path, monkeypatch) -> None:
    text = _split_sections(path)
    fast, slow = _read_both(path, monkeypatch, text)
    assert fast.to_xml_string() == mjcf.from_path(path).to_xml_string()  # merged as MuJoCo does
    _assert_same_model(fast, slow)


def test_a_repeated_walker_compiles_as_mujoco_compiles_it(monkeypatch) -> None:
    path = _walker("cmu_v2020")
    text = _split_sections(path)
    fast, slow = _read_both(path, monkeypatch, text)
    _assert_same_model(fast, slow)
    ours = mjcf.Physics.from_mjcf_model(fast).model
    spec = mujoco.MjSpec.from_string(text)
    spec.modelfiledir = str(path.parent)
    theirs = spec.compile()
    sizes = ("nbody", "njnt", "ngeom", "nu")
    assert [getattr(ours, n) for n in sizes] == [getattr(theirs, n) for n in sizes]
    assert ours.geom_size.tolist() == theirs.geom_size.tolist()


REPEATED = {
    "a later copy's attribute overrides": '<compiler angle="degree"/><compiler angle="radian"/>',
    "once-only children in two copies merge": (
        '<visual><global fovy="30"/></visual><visual><global azimuth="10" fovy="40"/></visual>'
    ),
    "two copies of <default>": (
        '<default><geom rgba="1 0 0 1"/></default><default><joint damping="1"/></default>'
    ),
    "bodies in both copies, interleaved": (
        '<worldbody><body name="a"/></worldbody><asset><texture name="t" builtin="flat" '
        'width="8" height="8"/></asset><worldbody><body name="b"><geom size="1"/></body>'
        "</worldbody>"
    ),
}


@pytest.mark.parametrize("case", sorted(REPEATED))
def test_repeated_sections_merge_as_element_by_element(case: str, monkeypatch) -> None:
    xml = f"<mujoco>{REPEATED[case]}<worldbody><geom size='1'/></worldbody></mujoco>"
    fast = mjcf.from_xml_string(xml)
    monkeypatch.setattr(fast_reader, "read", lambda *args: False)
    slow = mjcf.from_xml_string(xml)
    _assert_same_model(fast, slow)
    compiled = mjcf.Physics.from_mjcf_model(fast).model
    assert compiled.ngeom == mujoco.MjModel.from_xml_string(xml).ngeom


def test_synthetic_creatures_read_fast_and_compile(tmp_path: Path, monkeypatch) -> None:
    for shape in (synthetic.CMU_HUMANOID, synthetic.RODENT):
        path = tmp_path / f"{shape.name}.xml"
        path.write_text(synthetic.creature_xml(shape))
        fast, slow = _read_both(path, monkeypatch)
        assert fast.to_xml_string() == slow.to_xml_string()
        compiled = mjcf.Physics.from_mjcf_model(fast).model
        assert compiled.nbody == mujoco.MjModel.from_xml_path(str(path)).nbody


BAD = {
    "unknown attribute": ('<body name="a" pos="0 0 1" colour="red"/>', "colour"),
    "bad number": ('<body name="a" pos="0 0 x"/>', "pos"),
    "too many numbers": ('<body name="a" pos="0 0 1 2"/>', "pos"),
    "bad keyword": ('<body name="a"><joint type="hinj"/></body>', "hinj"),
    "unknown element": ('<body name="a"><gem/></body>', "gem"),
    "duplicate name": ('<body name="a"/><body name="a"/>', "already used"),
    "dangling reference": ('<body name="a" childclass="nope"/>', "nope"),
    "name with a separator": ('<body name="a/b"/>', "separator"),
    "two inertials": (
        '<body name="a"><inertial mass="1" pos="0 0 0"/><inertial mass="1" pos="0 0 0"/></body>',
        "only one",
    ),
    "the world's name": ('<body name="world"/>', "already used"),
    "a decimal too large for a float": (f'<geom size="1" rgba="{"9" * 39} 0 0 1"/>', "too large"),
    "a decimal too large for a double": (f'<body name="a" pos="1{"0" * 400} 0 0"/>', "too large"),
    "an exponent without digits": ('<body name="a" pos="1e+ 0 0"/>', "pos"),
    "an exponent too large for a float": ('<geom size="1" rgba="1e39 0 0 1"/>', "too large"),
    "a mantissa too large for a float": (f'<geom size="1" rgba="{"9" * 30}e9 0 0 1"/>', "large"),
    "a gear that is not finite": (
        '<body name="a"><joint name="j"/></body></worldbody><actuator>'
        '<motor joint="j" gear="INF"/></actuator><worldbody>',
        "gear",
    ),
    "a decimal too large, spelled": (
        '<geom size="1" rgba="' + "&#57;" * 39 + ' 0 0 1"/>',
        "too large",
    ),
}


# The same errors across the copies of a repeated section.
BAD_REPEATED = {
    "a name in both copies": ('<body name="a"/></worldbody><worldbody><body name="a"/>', "used"),
    "a reference to nothing in a later copy": (
        '<body name="a"/></worldbody><worldbody><body name="b" childclass="nope"/>',
        "nope",
    ),
    "an unknown attribute in a later copy": (
        '</worldbody><compiler angle="radian"/><compiler colour="red"/><worldbody>',
        "colour",
    ),
}


@pytest.mark.parametrize("case", sorted(BAD) + sorted(BAD_REPEATED))
def test_errors_are_raised_at_parse_time_as_element_by_element(case: str, monkeypatch) -> None:
    body, match = BAD[case] if case in BAD else BAD_REPEATED[case]
    xml = f"<mujoco><worldbody>{body}</worldbody></mujoco>"
    with pytest.raises(mjcf.Error, match=match) as fast:
        mjcf.from_xml_string(xml)
    monkeypatch.setattr(fast_reader, "read", lambda *args: False)
    with pytest.raises(mjcf.Error) as slow:
        mjcf.from_xml_string(xml)
    assert (type(fast.value), str(fast.value)) == (type(slow.value), str(slow.value))


# Texts for numbers and keywords in the forms a model might hold, well formed or not.
_WORDS = ["1", "-2", "+3", "0.5", ".5", "5.", "1e3", "1E-3", "-1.5e+2", "inf", "INF", "-INF",
          "+INF", "NaN", "nan", "0x10", "1_0", "1.0", "1,2", "true", "hinge", "", "1d", "--1",
          "1e", "1e+", "1.5E", ".e1", "5.e3", "1e5.5", "0b1", "\u0661", ".", "+", "-", "+.",
          "-.", "1e5e5", "1.2.3", "INFINITY", "Infinity", "-NaN", "e5", "E"]  # fmt: skip


def _texts() -> list[str]:
    texts = [w for w in _WORDS]
    texts += [" ".join(_WORDS[i : i + n]) for n in (2, 3, 4, 7) for i in range(0, 12, 3)]
    texts += ["  1 2 3 ", "\t1\t2", "1  2  3  4  5  6", " ".join(["1"] * 12)]
    return texts


# Decimals too large for a C float or a double, and their neighbours that fit.
_LONG = ["9" * 38, "9" * 39, "-" + "9" * 39, "1" * 400, "0." + "1" * 60, "3" + "4" * 38 + ".5",
         "1e38", "3.3e38", "3.5e38", "1e39", "-1e39", "1e+39", "1e308", "1e309", "1e-400",
         "9" * 29 + "e9", "9" * 30 + "e9", "1e09", "1.5e", "1e+", "1E-", "5.e", "5.E+3",
         "-INF", "INF", "NaN", "1e5 1e", "1e1e1", "2e-5"]  # fmt: skip


@pytest.mark.parametrize("exact", [False, True], ids=["fast", "exact"])
def test_the_xml_schema_accepts_no_value_the_converters_refuse(exact: bool) -> None:
    """The schema's value types are a subset of what the converters accept, for every
    attribute it types: so a document it accepts is one reading element by element
    accepts too. The fast schema takes decimals of any length: a document holding one
    too long for it is checked against the exact one (`xsd.needs_exact`)."""
    checked = {}
    for spec in _all_specs():
        for attribute in spec.attributes.values():
            kind = xsd._simple_type(attribute)
            if kind is not None:
                checked.setdefault(kind, attribute)
    assert len(checked) > 20
    definitions = xsd._reals(xsd._EXACT if exact else xsd._FAST) + "".join(
        xsd._simple_type_text(f"t{i}", k) for i, k in enumerate(checked)
    )
    elements = "".join(f'<xs:element name="e{i}" type="t{i}"/>' for i in range(len(checked)))
    schema = etree.XMLSchema(
        etree.fromstring(
            '<xs:schema xmlns:xs="http://www.w3.org/2001/XMLSchema">'
            f"{definitions}{elements}</xs:schema>"
        )
    )
    texts = _texts() + _LONG + [" ".join(["1", word]) for word in _LONG]
    texts += sorted({v for kind in checked if kind[0] == "keywords" for v in kind[1]})
    wrongly_accepted = []
    for i, attribute in enumerate(checked.values()):
        for text in texts:
            if not exact and xsd.needs_exact(text.encode(), "UTF-8"):
                continue  # checked against the exact schema
            element = etree.Element(f"e{i}")
            element.text = text
            if not schema.validate(element):
                continue
            try:
                attribute.converter.check_text(text)
            except ValueError:
                wrongly_accepted.append((attribute, text))
    assert wrongly_accepted == []


def test_a_document_that_could_hold_a_decimal_too_large_is_checked_exactly() -> None:
    assert not xsd.needs_exact(b'<mujoco><body pos="' + b"9" * 38 + b' 0 0"/></mujoco>', "UTF-8")
    assert xsd.needs_exact(b'<mujoco><body pos="' + b"9" * 39 + b' 0 0"/></mujoco>', "UTF-8")
    assert xsd.needs_exact(b'<mujoco><body pos="&#57;"/></mujoco>', "UTF-8")  # spelled
    assert xsd.needs_exact('<mujoco><body pos="1"/></mujoco>'.encode("utf-16"), "UTF-8")
    assert xsd.needs_exact(b"<mujoco/>", "cp037")  # EBCDIC digits are other bytes


def _all_specs():
    from mjcf import schema

    return schema.all_specs()


_FIRST_READS = """
import mjcf
from mjcf.io import fast_reader
from mjcf.io import xsd
path = {path!r}
first = mjcf.from_path(path).to_xml_string()
assert not xsd.is_made(), "the first model is read element by element"
reads = 1
while not xsd.is_made():
    assert mjcf.from_path(path).to_xml_string() == first
    reads += 1
print(reads, fast_reader._elements_read_slowly, fast_reader._ELEMENTS_BEFORE_SCHEMA)
"""


def test_a_process_reads_element_by_element_until_the_schema_pays() -> None:
    """The first documents of a process are read element by element, the same model,
    until they have cost what making the XML Schema costs; then it is made."""
    path = GYM_ASSETS / "humanoid.xml"
    elements = sum(1 for _ in etree.parse(str(path)).iter(etree.Element))
    done = subprocess.run(
        [sys.executable, "-c", _FIRST_READS.format(path=str(path))],
        capture_output=True, text=True, check=True, env=os.environ,
    )  # fmt: skip
    reads, counted, threshold = map(int, done.stdout.split())
    needed = -(-threshold // elements)  # reads to reach the count
    assert needed > 1
    assert (reads, counted) == (needed + 1, needed * elements)


def _fresh() -> mjcf.RootElement:
    return mjcf.from_path(GYM_ASSETS / "humanoid.xml")


def test_elements_not_built_yet_are_found_renamed_and_clash() -> None:
    model = _fresh()
    foot = model.find("geom", "left_foot")
    assert foot.parent.name == "left_foot" and foot.root is model and not foot.is_removed
    assert foot.full_identifier == "left_foot"
    with pytest.raises(mjcf.NameClashError, match="left_shin1"):
        model.worldbody.add("geom", name="left_shin1", size=[0.1])  # held by an unbuilt geom
    model.find("body", "right_thigh").name = "thigh"
    assert model.find("body", "thigh") is not None and model.find("body", "right_thigh") is None


def test_removing_a_subtree_not_built_frees_its_names() -> None:
    model = _fresh()
    model.find("body", "torso").remove()
    assert model.find("geom", "right_foot") is None
    model.worldbody.add("body", name="right_foot").add("geom", name="right_foot", size=[0.1])
    assert model.find("geom", "right_foot").parent.name == "right_foot"


def test_a_model_just_read_pickles_copies_attaches_and_compiles() -> None:
    written = _fresh().to_xml_string()
    assert pickle.loads(pickle.dumps(_fresh())).to_xml_string() == written
    assert copy.deepcopy(_fresh()).to_xml_string() == written
    scene = mjcf.RootElement(model="scene")
    scene.attach(_fresh())
    scene.attach(_fresh())
    assert mjcf.Physics.from_mjcf_model(scene).model.nbody == 1 + 2 * 13
