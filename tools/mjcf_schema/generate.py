"""Generate ``mjcf_schema.json``, MuJoCo's MJCF schema as data, from the installed mujoco.

    python -m tools.mjcf_schema.generate          # rewrite mjcf/schema/mjcf_schema.json
    python -m tools.mjcf_schema.generate --check  # exit 1 if the checked-in file is stale

Run it after upgrading mujoco and commit the result; it reads about 15,000 probe
documents in some 12 s of CPU (the test that the checked-in file is current runs
it in CI). Where the data comes from:

* the element tree, attribute names and order: ``XMLschema.rst`` in the wheel;
* attribute types, keywords, defaults, required-ness: ``XMLreference.rst`` and
  the ``modeling.rst`` sections it points to ("See :ref:`CSensor`");
* how two models' global settings merge when one is attached to the other (``merge``:
  ``min``, ``max`` or ``or``): the merging table of ``programming/modeledit.rst``;
* what the documentation does not say (which element a name refers to, which
  strings are file paths): the hand-kept tables in ``_annotations.py``; a string
  attribute they do not cover stops the generator with a list to decide on;
* what only MuJoCo's XML reader knows, probed with ``MjSpec.from_string``
  (``_probe.py``, no compiling; in a child process, ``_reader.py``): how many
  numbers each attribute takes, which children ``worldbody``, ``frame`` and
  ``replicate`` accept, which object types name things, which keyword
  attributes take a list. Every element, parent, attribute, keyword, int/real
  type and required attribute the documents give is also checked against the
  reader; where they disagree the reader wins and a note is logged (shown unless
  ``-q``);
* what the reader accepts beyond the documentation (``_refine.py``): which
  children may repeat under which parent, blank values, C-float reals, bounds on
  numbers, keyword case, spacing and integer forms, keyword lists and their order,
  text grammars, and rules between attributes ("at most one of").

``python -m tools.mjcf_schema.check`` then compares mjcf with the reader document by
document, and reports every disagreement left.

The file maps element keys (MuJoCo's doc anchors: ``body-geom``,
``default-geom``, ``actuator-position``; plus ``worldbody``) to
``{"tag", "namespace", "repeated", "attributes", "children"}`` (with
``"repeated_in"``, parents under which an element that otherwise appears once may
repeat, ``"matters_empty"`` for a once-only element that changes the model by being
there even empty, and ``"rules"`` between attributes, when there are any). Attribute
specs have a ``type`` of ``identifier``, ``string``, ``file``, ``reference``
(``namespace``, or ``namespace_from``/``namespace_map``; ``list``),
``keyword`` (``values``; ``list``) or ``int``/``real`` (``min``/``max``
numbers, counting from 1; ``max`` null when unbounded; ``gaps``: counts between
them refused; ``multiple_of``), with
``required`` and ``default``, and ``merge`` where the documentation gives one.
"""

from __future__ import annotations

import argparse
import json
import logging
import re
import sys
from pathlib import Path

import mujoco

from mjcf import schema
from tools.mjcf_schema import _annotations, _probe, _refine, _rules
from tools.mjcf_schema._docs import (
    BODY,
    DEFAULT,
    META,
    ROOT,
    WORLDBODY,
    Attribute,
    Element,
    SchemaError,
    doc_dir,
    elements_from_docs,
    listed_values,
    merge_rules_from_docs,
)
from tools.mjcf_schema._probe import Probe, note

OUTPUT = schema.DATA_FILE
# Elements holding the kinematic tree; their children are probed.
TREE_HOLDERS = (WORLDBODY, BODY, *META)

logger = logging.getLogger(__name__)


# -- what the documentation leaves open ----------------------------------------------


def classify_strings(elements: dict[str, Element]) -> None:
    """Give each string attribute its kind: identifier, reference, file or string."""
    unclassified = []
    for key, element in elements.items():
        for name, attribute in element.attributes.items():
            if attribute.kind != "string":
                continue
            override = _annotations.BY_ELEMENT.get((key, name))
            choice = override or _annotations.REFERENCES.get(name)
            if name == "name" or (key == DEFAULT and name == "class"):
                attribute.kind = "identifier"
            elif override is None and name in _annotations.NAMESPACE_FROM:
                attribute.kind = "reference"
                attribute.namespace_from = _annotations.NAMESPACE_FROM[name]
            elif choice not in (None, "string", "file"):
                attribute.kind, attribute.namespace = "reference", choice
            elif choice == "file" or (choice is None and name in _annotations.FILES):
                attribute.kind = "file"
            elif choice is None and name not in _annotations.PLAIN_STRINGS:
                unclassified.append(f"{key}/{name}")
            if attribute.kind != "reference":
                attribute.is_list = False
    if unclassified:
        raise SchemaError(
            "string attributes not classified in _annotations.py (reference, file or "
            "plain string?): " + ", ".join(unclassified)
        )


def assign_namespaces(elements: dict[str, Element], object_types: list[str]) -> None:
    """The namespace of each element's name: its object type, or its section's."""
    parents: dict[str, list[str]] = {}
    for key, element in elements.items():
        for child in element.children:
            parents.setdefault(child, []).append(key)
    problems = []
    for key, element in elements.items():
        if key == DEFAULT:
            element.namespace = DEFAULT
        elif key in _annotations.ELEMENT_NAMESPACES:
            element.namespace = _annotations.ELEMENT_NAMESPACES[key]
        elif "name" in element.attributes:
            # A grouping section without attributes named for an object type
            # (<sensor>, <actuator>) names the kinds below it (<touch>, <motor>).
            sections = [
                elements[p].tag
                for p in parents.get(key, [])
                if not elements[p].attributes and elements[p].tag in object_types
            ]
            if sections:
                element.namespace = sections[0]
            elif element.tag in object_types:
                element.namespace = element.tag
            else:
                problems.append(key)
    if problems:
        raise SchemaError("named elements without a namespace: " + ", ".join(problems))
    namespaces = {e.namespace for e in elements.values() if e.namespace}
    for key, element in elements.items():
        for attribute in element.attributes.values():
            if attribute.namespace_from:
                selector = element.attributes[attribute.namespace_from]
                attribute.namespace_map = {
                    value: _annotations.OBJECT_TYPE_ALIASES.get(value, value)
                    for value in selector.values
                }
                targets: set[str | None] = set(attribute.namespace_map.values())
            elif attribute.kind == "reference":
                targets = {attribute.namespace}
            else:
                continue
            if not targets <= namespaces:
                raise SchemaError(
                    f"{key}/{attribute.name} refers to unknown {targets - namespaces}"
                )


# -- the reader ---------------------------------------------------------------------


def complete_with_probes(elements: dict[str, Element], edges: list[tuple[str, str]]) -> None:
    """Check the documented schema against MuJoCo's reader and fill in what it knows."""
    prober = _probe.Prober(elements, ROOT)
    prober.set_paths()
    _object_types(prober, elements)
    _tree_holders(prober, elements)
    _required(prober, elements)
    _enumerated_strings(prober, elements)
    _refine.keyword_lists(prober, elements)
    _refine.text_formats(prober, elements)
    _minimal(prober, elements)
    _edges(prober, elements, edges)
    _values(prober, elements)
    _number_kinds(prober, elements)
    for key, element in elements.items():
        for attribute in element.attributes.values():
            if attribute.kind in ("int", "real"):
                _arity(prober, key, attribute)
    _refine.repetition(prober, elements)
    _refine.empty_presence(prober, elements)
    _refine.blanks(prober, elements)
    _refine.float_precision(prober, elements)
    _refine.bounds(prober, elements)
    _refine.keyword_forms(prober, elements)
    _rules.rules(prober, elements)
    _refine.reference_lists(elements, ROOT)
    logger.info("probed MuJoCo's reader with %d documents", prober.parses)


def _object_types(prober: _probe.Prober, elements: dict[str, Element]) -> None:
    """Keywords over every named type; then the element namespaces that build on them."""
    documented = [
        (key, a)
        for key, element in elements.items()
        for a in element.attributes.values()
        if a.any_object_type
    ]
    accepted = {
        (key, a.name): _probe.accepted_keywords(prober, key, a.name, _probe.OBJECT_TYPES)
        for key, a in documented
    }
    object_types = [t for t in _probe.OBJECT_TYPES if all(t in ok for ok in accepted.values())]
    for key, attribute in documented:
        attribute.values = object_types
        if len(accepted[key, attribute.name]) == len(_probe.OBJECT_TYPES):
            note(f"{key}/{attribute.name}: the reader accepts any object type name")
    assign_namespaces(elements, object_types)


def _tree_holders(prober: _probe.Prober, elements: dict[str, Element]) -> None:
    """Children of worldbody, body, frame, replicate, default; worldbody's attributes."""
    body, default = elements[BODY], elements[DEFAULT]
    candidates = list(body.children)
    for key in TREE_HOLDERS:
        documented = list(elements[key].children)
        allowed = _probe.allowed_children(prober, key, candidates)
        elements[key].children = allowed
        if key == BODY and allowed != documented:
            note(f"body: documented children {documented}, the reader accepts {allowed}")
    by_tag = {elements[key].tag: key for key in candidates}
    by_tag.update({elements[key].tag: key for key in default.children})
    allowed = _probe.allowed_children(prober, DEFAULT, list(by_tag.values()))
    if set(allowed) != set(default.children):
        raise SchemaError(f"default: documented {default.children}, reader accepts {allowed}")
    accepted = _probe.accepted_attributes(prober, WORLDBODY, list(body.attributes.values()))
    elements[WORLDBODY].attributes = {name: body.attributes[name] for name in accepted}


def _enumerated_strings(prober: _probe.Prober, elements: dict[str, Element]) -> None:
    """Strings the reader looks up in a list are keywords; their values are in the docs."""
    for key, element in elements.items():
        for attribute in element.attributes.values():
            if attribute.kind != "string":
                continue
            error = prober.error(Probe(key, {attribute.name: "probe_text"}))
            if error is None or _probe.LIST_READER in error:  # lists: _refine.keyword_lists
                continue
            if not _probe.bad_keyword(error, "probe_text"):
                note(f"{key}/{attribute.name}: the reader checks the text: {error}")
                continue
            values = listed_values(attribute.description)
            if not values:
                raise SchemaError(f"{key}/{attribute.name}: a keyword, but no values documented")
            note(f"{key}/{attribute.name}: documented string, the reader takes keywords {values}")
            attribute.kind, attribute.values = "keyword", values


def _required(prober: _probe.Prober, elements: dict[str, Element]) -> None:
    """Attributes the reader requires that the documentation calls optional."""
    pending = list(elements)
    while pending:
        keys, pending = pending, []
        errors = prober.errors([Probe(key) for key in keys])
        for key, error in zip(keys, errors, strict=True):
            missing = re.search(r"required attribute missing: '(\w+)'", error or "")
            if missing:
                note(f"{key}/{missing.group(1)}: documented optional, the reader requires it")
                elements[key].attributes[missing.group(1)].required = True
                pending.append(key)


def _minimal(prober: _probe.Prober, elements: dict[str, Element]) -> None:
    """Each element with its required attributes is accepted; without one, rejected."""
    prober.require_accepted([Probe(key) for key in elements])
    for key, element in elements.items():
        for attribute in element.attributes.values():
            omitted = Probe(key, omit=(attribute.name,))
            if attribute.required and prober.error(omitted) is None:
                note(f"{key}/{attribute.name}: documented required, the reader does not require it")
                attribute.required = False


def _edges(
    prober: _probe.Prober, elements: dict[str, Element], edges: list[tuple[str, str]]
) -> None:
    """Each documented child is accepted under its parent, repeated if it may repeat."""
    probes = [
        Probe(child, parent=parent, copies=2 if elements[child].repeated else 1)
        for parent, child in edges
    ]
    prober.require_accepted(probes)  # how often, everywhere: _refine.repetition


def _values(prober: _probe.Prober, elements: dict[str, Element]) -> None:
    """Each attribute and each keyword value is known to the reader.

    A probe whose value the reader reads and then rejects for what it means
    (a mesh ``builtin`` without its ``params``) still shows the attribute and
    the keyword are known; only errors about them count against the schema.
    """
    probes: list[tuple[str, Attribute, str]] = []
    for key, element in elements.items():
        for attribute in element.attributes.values():
            values = attribute.values if attribute.kind == "keyword" else [prober.value(attribute)]
            probes.extend((key, attribute, value) for value in values)
            if key in META and not _probe.is_read(prober, key, attribute):
                raise SchemaError(f"{key}/{attribute.name}: MuJoCo ignores this attribute")
    errors = prober.errors([Probe(key, {a.name: value}) for key, a, value in probes])
    unknown = []
    for (key, attribute, value), error in zip(probes, errors, strict=True):
        if error and _probe.unrecognized(error, attribute.name):
            unknown.append(f"{key}/{attribute.name}")
        elif error and attribute.count and _probe.bad_count(error, attribute.name):
            note(f"{key}/{attribute.name}: the reader rejects the documented {attribute.count}")
            attribute.count = None  # probe from scratch
        elif error and _probe.bad_keyword(error, value):
            note(f"{key}/{attribute.name}: the reader rejects documented keyword {value!r}")
            attribute.values.remove(value)
    if unknown:
        raise SchemaError("documented attributes MuJoCo's reader does not know: " + str(unknown))
    for key, element in elements.items():
        for attribute in element.attributes.values():
            if attribute.kind != "keyword" or attribute.any_object_type:
                continue
            error = prober.error(Probe(key, {attribute.name: "probe_keyword"}))
            if not (error and _probe.bad_keyword(error, "probe_keyword", attribute.name)):
                note(f"{key}/{attribute.name}: the reader accepts any keyword")
            elif _probe.LIST_READER in error and not attribute.is_list:  # a list? try two
                pair = {attribute.name: " ".join(attribute.values[:2])}
                attribute.is_list = prober.error(Probe(key, pair)) is None


def _number_kinds(prober: _probe.Prober, elements: dict[str, Element]) -> None:
    """Documented ints are read as integers and reals as reals: only ints refuse 0.5."""
    numbers = [
        (key, attribute)
        for key, element in elements.items()
        for attribute in element.attributes.values()
        if attribute.kind in ("int", "real")
    ]
    probes = [Probe(key, {a.name: " ".join(["0.5"] * (a.count or 1))}) for key, a in numbers]
    reals = [i for i, (_, a) in enumerate(numbers) if a.kind == "real"]
    errors = dict(zip(reals, prober.errors([probes[i] for i in reals]), strict=True))
    for index, (key, attribute) in enumerate(numbers):
        error = errors[index] if index in errors else prober.error(probes[index])
        kind = "int" if error and _probe.bad_count(error, attribute.name) else "real"
        if kind != attribute.kind:
            note(f"{key}/{attribute.name}: documented {attribute.kind}, the reader reads {kind}")
            attribute.kind = kind


def _arity(prober: _probe.Prober, key: str, attribute: Attribute) -> None:
    arity = _probe.arity(prober, key, attribute)
    attribute.min, attribute.max, attribute.gaps = arity.min, arity.max, arity.gaps
    documented = f"documented {attribute.count or 'model-dependent'} numbers"
    if attribute.count is not None and arity.max != attribute.count:
        note(f"{key}/{attribute.name}: {documented}, the reader takes up to {arity.max}")


# -- output -------------------------------------------------------------------------


def build(docs: Path | None = None) -> dict:
    """The schema of the installed mujoco, as the JSON-ready dictionary."""
    elements, edges = elements_from_docs(docs or doc_dir())
    merge_rules_from_docs(docs or doc_dir(), elements)
    classify_strings(elements)
    complete_with_probes(elements, edges)
    return {
        "mujoco_version": mujoco.__version__,
        "root": ROOT,
        "elements": {key: element.to_json() for key, element in elements.items()},
    }


def dumps(schema: dict) -> str:
    """The JSON text, one line per attribute so that diffs show what changed."""

    def element(key: str, data: dict) -> str:
        fields = [
            f"      {json.dumps(f)}: {json.dumps(data[f])}"
            for f in ("tag", "namespace", "repeated")
        ]
        specs = ",\n".join(
            f"        {json.dumps(name)}: {json.dumps(spec)}"
            for name, spec in data["attributes"].items()
        )
        fields.append('      "attributes": {' + (f"\n{specs}\n      " if specs else "") + "}")
        fields.append(f'      "children": {json.dumps(data["children"])}')
        if data.get("repeated_in"):
            fields.append(f'      "repeated_in": {json.dumps(data["repeated_in"])}')
        if data.get("matters_empty"):
            fields.append('      "matters_empty": true')
        if data.get("rules"):
            rules = ",\n".join(f"        {json.dumps(rule)}" for rule in data["rules"])
            fields.append(f'      "rules": [\n{rules}\n      ]')
        return f"    {json.dumps(key)}: {{\n" + ",\n".join(fields) + "\n    }"

    head = "".join(
        f"  {json.dumps(k)}: {json.dumps(schema[k])},\n" for k in ("mujoco_version", "root")
    )
    elements = ",\n".join(element(key, data) for key, data in schema["elements"].items())
    return "{\n" + head + '  "elements": {\n' + elements + "\n  }\n}\n"


def main(argv: list[str] | None = None) -> int:
    """Command line entry point; returns the exit status."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--check", action="store_true", help="fail if the JSON file is stale")
    parser.add_argument("--output", type=Path, default=OUTPUT, help="file to write or check")
    parser.add_argument("-q", "--quiet", action="store_true", help="do not log notes")
    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.WARNING if args.quiet else logging.INFO, format="%(message)s")
    text = dumps(build())
    if args.check:
        current = args.output.read_text() if args.output.exists() else ""
        if current != text:
            logger.error("%s is stale; run `python -m tools.mjcf_schema.generate`", args.output)
            return 1
        return 0
    args.output.write_text(text)
    logger.info("wrote %s", args.output)
    return 0


if __name__ == "__main__":
    sys.exit(main())
