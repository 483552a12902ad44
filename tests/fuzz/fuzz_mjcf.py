"""Coverage-guided fuzzing of mjcf's reader, writer and compiler with atheris (by hand).

    pip install atheris
    python tests/fuzz/fuzz_mjcf.py -max_total_time=600 tests/fuzz/corpus

Seeds are the MJCF files shipped with gymnasium and mujoco (copied into the corpus
folder on first run), and a zip of one with its meshes. Each input is read as MJCF text
(written and compiled, within `mjcf.budget`) and as a zip archive (`mjcf.from_zip`, within
small unpacking limits). The only exceptions allowed out of `mjcf` are `mjcf.Error`
subclasses; anything else is a crash that atheris reports with the input that caused
it. Add each such input as a regression case to `tests/mjcf/test_hostile_input.py`.
"""

from __future__ import annotations

import contextlib
import io
import os
import shutil
import sys
from pathlib import Path

import atheris

with atheris.instrument_imports():
    import mjcf

REPO = Path(__file__).resolve().parents[2]
_ZIP_LIMITS = mjcf.archives.Limits(size=1 << 24, ratio=100)


def _seed_corpus(folder: Path) -> None:
    import gymnasium
    import mujoco

    folder.mkdir(parents=True, exist_ok=True)
    if any(folder.iterdir()):
        return
    sources = list((Path(gymnasium.__file__).parent / "envs/mujoco/assets").glob("*.xml"))
    sources += list((Path(mujoco.__file__).parent / "testdata").glob("*.xml"))
    for source in sources:
        shutil.copy(source, folder / source.name)
    model = mjcf.from_path(Path(mujoco.__file__).parent / "testdata" / "model.xml")
    mjcf.export_with_assets_as_zip(model, folder / "model.zip")


def test_one_input(data: bytes) -> None:
    """Read, write and compile one input, and read it as a zip; only mjcf errors may
    escape."""
    try:
        model = mjcf.from_xml_string(data, model_dir=str(REPO))
        model.to_xml_string()
        mjcf.Physics.from_mjcf_model(model)
    except mjcf.Error:
        pass
    with contextlib.suppress(mjcf.Error):
        mjcf.from_zip(io.BytesIO(data), limits=_ZIP_LIMITS)


def main() -> None:
    corpus = [arg for arg in sys.argv[1:] if not arg.startswith("-")]
    for folder in corpus:
        _seed_corpus(Path(folder))
    os.environ.setdefault("MUJOCO_GL", "egl")
    atheris.Setup(sys.argv, test_one_input)
    atheris.Fuzz()


if __name__ == "__main__":
    main()
