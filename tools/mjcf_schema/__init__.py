"""The build-time tooling of mjcf's schema: the generator of the data `mjcf.schema` loads
(`mjcf/schema/mjcf_schema.json`), and the differential check of mjcf against MuJoCo's
XML reader. Run from the repository's root:

    python -m tools.mjcf_schema.generate          # rewrite the JSON from the installed mujoco
    python -m tools.mjcf_schema.generate --check  # exit 1 if the checked-in file is stale
    python -m tools.mjcf_schema.check --sample    # the deterministic sample the tests run
    python -m tools.mjcf_schema.check             # the full sweep (minutes)

A user's program needs none of this: the wheel carries `mjcf.schema` and its JSON only,
and `mjcf` never imports this package (tests/mjcf/test_schema_packaging.py). The tooling
uses mjcf through its public names (the check compares `mjcf.from_xml_string` with MuJoCo).
"""
