"""The generated MJCF schema (mjcf/schema/mjcf_schema.json): current with the installed
mujoco, complete against its XML reference, and right about what MuJoCo's reader accepts."""

from __future__ import annotations

import json
import re
from pathlib import Path

import gymnasium
import mujoco
import pytest
from lxml import etree

from tests.conftest import MENAGERIE
from tools.mjcf_schema import _annotations, _docs, generate

SCHEMA_FILE = generate.OUTPUT
DOCS = _docs.doc_dir()
GYM_ASSETS = Path(gymnasium.__file__).parent / "envs" / "mujoco" / "assets"
MUJOCO_TESTDATA = Path(mujoco.__file__).parent / "testdata"


@pytest.fixture(scope="module")
def schema() -> dict:
    return json.loads(SCHEMA_FILE.read_text())


@pytest.fixture(scope="module")
def elements(schema: dict) -> dict:
    return schema["elements"]


# -- the file is what the installed mujoco gives ------------------------------------------


def test_checked_in_schema_is_for_the_installed_mujoco(schema: dict) -> None:
    assert schema["mujoco_version"] == mujoco.__version__


# Generating probes MuJoCo's reader with about 15,000 documents (some 12 s of CPU).
def test_checked_in_schema_is_what_the_installed_mujoco_generates(schema: dict) -> None:
    fresh = generate.build()
    stale = sorted(
        key
        for key in fresh["elements"].keys() | schema["elements"].keys()
        if fresh["elements"].get(key) != schema["elements"].get(key)
    )
    assert not stale, f"regenerate with `python -m tools.mjcf_schema.generate`; differs: {stale}"
    assert generate.dumps(fresh) == SCHEMA_FILE.read_text()
    assert schema["mujoco_version"] == mujoco.__version__


def test_every_element_and_attribute_of_the_xml_reference_is_in_the_schema(
    elements: dict,
) -> None:
    """Read XMLschema.rst with a plain regex (not the generator's parser)."""
    text = (DOCS / "XMLschema.rst").read_text()
    missing = []
    current = None
    for line in text.splitlines():
        dropdown = re.search(r"\.\. dropdown:: :ref:`([^<]+)<([^>]+)>`", line)
        item = re.fullmatch(r"\s+:ref:`(\w+)<([\w-]+)>`", line)
        if dropdown:
            current = dropdown.group(2)
            if current not in elements:
                missing.append(current)
        elif item and current in elements and item.group(1) not in elements[current]["attributes"]:
            missing.append(item.group(2))
    reference = (DOCS / "XMLreference.rst").read_text()
    for meta, key in (("frame", "body-frame"), ("replicate", "replicate")):
        for name in re.findall(rf"^\.\. _{meta}-(\w+):$", reference, re.MULTILINE):
            if name not in elements[key]["attributes"]:
                missing.append(f"{meta}-{name}")
    assert not missing


def test_every_child_key_exists_and_tags_are_unique_under_each_parent(elements: dict) -> None:
    for key, element in elements.items():
        tags = [elements[child]["tag"] for child in element["children"]]
        assert len(tags) == len(set(tags)), key


def test_every_reference_points_into_a_namespace_some_element_has(elements: dict) -> None:
    namespaces = {e["namespace"] for e in elements.values() if e["namespace"]}
    used = set()
    for element in elements.values():
        for spec in element["attributes"].values():
            if spec["type"] == "reference":
                used |= set(spec.get("namespace_map", {}).values()) | {spec.get("namespace")}
    used.discard(None)
    assert used <= namespaces, used - namespaces
    assert {"body", "joint", "geom", "site", "material", "mesh", "default"} <= used


# -- facts a user relies on ------------------------------------------------------------


def test_geom_size_takes_one_to_three_numbers_and_quat_exactly_four(elements: dict) -> None:
    for key in ("body-geom", "default-geom"):
        size = elements[key]["attributes"]["size"]
        assert (size["type"], size["min"], size["max"]) == ("real", 1, 3)
    for key in ("body", "body-geom", "body-site", "body-camera", "body-frame"):
        quat = elements[key]["attributes"]["quat"]
        assert (quat["min"], quat["max"], quat["default"]) == (4, 4, "1 0 0 0"), key


def test_user_data_and_mesh_vertices_are_unbounded(elements: dict) -> None:
    assert elements["body-geom"]["attributes"]["user"]["max"] is None
    vertex = elements["asset-mesh"]["attributes"]["vertex"]
    assert (vertex["max"], vertex["multiple_of"]) == (None, 3)


def test_option_integrator_is_a_keyword_defaulting_to_euler(elements: dict) -> None:
    integrator = elements["option"]["attributes"]["integrator"]
    assert integrator["type"] == "keyword"
    assert {"Euler", "RK4", "implicit", "implicitfast"} <= set(integrator["values"])
    assert integrator["default"] == "Euler"


def test_actuators_name_joints_tendons_and_sites(elements: dict) -> None:
    actuators = [key for key in elements if key.startswith("actuator-")]
    assert {"actuator-motor", "actuator-position", "actuator-general"} <= set(actuators)
    for key in actuators:
        attributes = elements[key]["attributes"]
        assert elements[key]["namespace"] == "actuator"
        if "joint" in attributes:
            assert attributes["joint"] == {
                "type": "reference",
                "namespace": "joint",
                "required": False,
            }
        if "site" in attributes:
            assert attributes["site"]["namespace"] == "site"


def test_sensor_objname_namespace_follows_objtype(elements: dict) -> None:
    objname = elements["sensor-framepos"]["attributes"]["objname"]
    assert objname["namespace_from"] == "objtype"
    assert objname["namespace_map"]["xbody"] == "body"
    assert objname["namespace_map"]["site"] == "site"
    assert set(objname["namespace_map"]) == set(
        elements["sensor-framepos"]["attributes"]["objtype"]["values"]
    )
    assert all(e["namespace"] == "sensor" for k, e in elements.items() if k.startswith("sensor-"))


def test_kinematic_tree_children(elements: dict) -> None:
    body, worldbody = elements["body"]["children"], elements["worldbody"]["children"]
    assert {"body", "body-frame", "replicate", "body-geom", "body-joint"} <= set(body)
    assert {"body", "body-frame", "replicate", "body-geom"} <= set(worldbody)
    assert not {"body-inertial", "body-joint", "body-freejoint"} & set(worldbody)
    assert "body-joint" not in elements["replicate"]["children"]  # wrap joints in a body
    assert {"body-frame", "body-joint", "body"} <= set(elements["body-frame"]["children"])
    assert "default" in elements["default"]["children"]
    assert "worldbody" in elements["mujoco"]["children"]
    assert "body" not in elements["mujoco"]["children"]


def test_worldbody_takes_no_attributes(elements: dict) -> None:
    assert elements["worldbody"]["attributes"] == {}
    assert elements["worldbody"]["namespace"] is None


def test_composite_is_gone(elements: dict) -> None:
    assert not [k for k, e in elements.items() if "composite" in k or e["tag"] == "composite"]


def test_frame_attributes_include_mujoco_4_scaling(elements: dict) -> None:
    frame = elements["body-frame"]
    assert frame["namespace"] == "frame"
    attributes = frame["attributes"]
    assert attributes["name"]["type"] == "identifier"
    assert attributes["childclass"] == {
        "type": "reference",
        "namespace": "default",
        "required": False,
    }
    assert {"pos", "quat", "axisangle", "xyaxes", "zaxis", "euler"} <= attributes.keys()
    assert (attributes["scale"]["min"], attributes["scale"]["max"]) == (1, 3)
    assert attributes["scaling"]["values"] == ["similar", "geometry"]
    assert "massscale" in attributes


def test_identifiers_and_default_classes(elements: dict) -> None:
    assert elements["default"]["attributes"]["class"]["type"] == "identifier"
    assert elements["default"]["namespace"] == "default"
    assert elements["body-freejoint"]["namespace"] == "joint"
    assert elements["equality-weld"]["namespace"] == "equality"
    assert elements["tendon-fixed"]["namespace"] == "tendon"
    for key, element in elements.items():
        for name, spec in element["attributes"].items():
            if name == "class" and key != "default":
                assert spec["namespace"] == "default", key
            if spec["type"] == "identifier":
                assert element["namespace"], key


def test_file_attributes(elements: dict) -> None:
    assert elements["asset-mesh"]["attributes"]["file"]["type"] == "file"
    texture = elements["asset-texture"]["attributes"]
    assert all(texture[f"file{side}"]["type"] == "file" for side in ("right", "left", "up"))
    assert elements["compiler"]["attributes"]["meshdir"]["type"] == "string"
    assert elements["body-attach"]["attributes"]["model"]["namespace"] == "model"


def test_sections_may_repeat_and_singletons_do_not(elements: dict) -> None:
    assert elements["option"]["repeated"] and elements["body-geom"]["repeated"]
    assert not elements["option-flag"]["repeated"]
    assert not elements["body-inertial"]["repeated"]
    assert not elements["mujoco"]["repeated"]


# -- the generator refuses what it cannot decide ------------------------------------------


def test_an_unclassified_string_attribute_stops_the_generator(monkeypatch) -> None:
    elements, _ = _docs.elements_from_docs(DOCS)
    monkeypatch.setattr(_annotations, "PLAIN_STRINGS", _annotations.PLAIN_STRINGS - {"meshdir"})
    with pytest.raises(_docs.SchemaError, match="compiler/meshdir"):
        generate.classify_strings(elements)


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ('real(3), "0 0 0"', ("real", 3, None, "0 0 0", False)),
        ('real(1 or 3), "1"', ("real", 3, None, "1", False)),
        ("real(3*nvert), optional", ("real", None, 3, None, False)),
        ('real(nuser_body), "0 0 ..."', ("real", None, None, None, False)),
        ('real(10), "1 0 ... 0"', ("real", 10, None, "1 0 0 0 0 0 0 0 0 0", False)),
        ("int(3*nface), optional", ("int", None, 3, None, False)),
        ('int, "-1"', ("int", 1, None, "-1", False)),
        ("string, required", ("string", None, None, None, True)),
        ("string, required (except at the top level)", ("string", None, None, None, False)),
        (
            '[radian, degree], "degree" for MJCF, always "radian" for URDF',
            ("keyword", None, None, "degree", False),
        ),
        ('bool, "false"', ("keyword", None, None, "false", False)),
    ],
)
def test_documented_value_text(text: str, expected: tuple) -> None:
    attribute = _docs.parse_value("a", text)
    got = (
        attribute.kind,
        attribute.count,
        attribute.multiple_of,
        attribute.default,
        attribute.required,
    )
    assert got == expected


def test_string_lists_are_lists() -> None:
    assert _docs.parse_value("body", "string(nvert or 1), required").is_list


# -- the schema agrees with MuJoCo ---------------------------------------------------------


def real_models() -> list[Path]:
    models = sorted(GYM_ASSETS.glob("*.xml")) + sorted(MUJOCO_TESTDATA.glob("*.xml"))
    return models + sorted(MENAGERIE.glob("*/*.xml"))


def violations(node: etree._Element, key: str, elements: dict, path: str) -> list[str]:
    """What in this XML element the schema would reject."""
    element, found = elements[key], []
    for name, value in node.attrib.items():
        spec = element["attributes"].get(name)
        if spec is None:
            found.append(f"{path}: attribute {name!r}")
        elif spec["type"] in ("int", "real"):
            count = len(value.split())
            if count < spec["min"] or (spec["max"] is not None and count > spec["max"]):
                found.append(f"{path}: {name}={value!r}")
        elif spec["type"] == "keyword":
            words = value.split() if spec.get("list") else [value]
            found.extend(f"{path}: {name}={value!r}" for w in words if w not in spec["values"])
    children = {elements[child]["tag"]: child for child in element["children"]}
    for child in node:
        if isinstance(child.tag, str) and child.tag != "include":
            if child.tag in children:
                found += violations(child, children[child.tag], elements, f"{path}/{child.tag}")
            else:
                found.append(f"{path}: child <{child.tag}>")
    return found


@pytest.mark.parametrize("model", real_models(), ids=lambda path: path.name)
def test_models_mujoco_loads_fit_the_schema(model: Path, elements: dict) -> None:
    mujoco.MjSpec.from_file(str(model))
    root = etree.parse(str(model)).getroot()
    assert violations(root, "mujoco", elements, "mujoco") == []


# Minimal contexts written by hand (not by the generator's prober): the element is "{}".
CONTEXTS = {
    "option": "<option {}/>",
    "compiler": "<compiler {}/>",
    "visual-global": "<visual><global {}/></visual>",
    "body": "<worldbody><body {}/></worldbody>",
    "body-geom": "<worldbody><body><geom {}/></body></worldbody>",
    "body-joint": "<worldbody><body><joint {}/></body></worldbody>",
    "body-site": "<worldbody><site {}/></worldbody>",
    "body-camera": "<worldbody><camera {}/></worldbody>",
    "body-light": "<worldbody><light {}/></worldbody>",
    "body-inertial": '<worldbody><body><inertial pos="0 0 0" mass="1" {}/></body></worldbody>',
    "body-frame": "<worldbody><frame {}/></worldbody>",
    "default-geom": "<default><geom {}/></default>",
    "tendon-spatial": "<tendon><spatial {}/></tendon>",
    "actuator-position": '<actuator><position joint="j" {}/></actuator>',
    "actuator-general": '<actuator><general joint="j" {}/></actuator>',
    "sensor-touch": '<sensor><touch site="s" {}/></sensor>',
    "keyframe-key": "<keyframe><key {}/></keyframe>",
}


def reader_accepts(xml: str, name: str) -> bool:
    try:
        mujoco.MjSpec.from_string(f"<mujoco>{xml}</mujoco>")
    except ValueError as error:
        return f"attribute '{name}'" not in str(error)
    return True


def test_arity_matches_what_mujoco_reads_for_every_count(elements: dict) -> None:
    """Every count from 1 to max + 1 (or min + 3 when unbounded), not only the boundaries."""
    wrong = []
    for key, context in CONTEXTS.items():
        for name, spec in elements[key]["attributes"].items():
            if spec["type"] not in ("int", "real") or f'{name}="' in context:
                continue
            top = (spec["max"] or spec["min"] + 2) + 1
            for count in range(1, top + 1):
                expected = spec["min"] <= count and (spec["max"] is None or count <= spec["max"])
                value = " ".join(["1"] * count)
                if reader_accepts(context.format(f'{name}="{value}"'), name) != expected:
                    wrong.append(f"{key}/{name} with {count} numbers")
    # MuJoCo reads frame scale as 1 or 3 numbers; min/max cannot say "not 2".
    assert wrong == ["body-frame/scale with 2 numbers"]
