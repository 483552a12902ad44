"""Ours against dm_control's own `composer.variation` (from the published wheel, fetched at
test time, loaded under another name): the same constructor arguments and the same seeded
random state give the same values, call after call, for every class, nested parameters,
initial-value shapes and the variators on real elements."""

from __future__ import annotations

import importlib
import sys
import zipfile

import numpy as np
import pytest

import mjcf
from composer import variation
from composer.variation import (
    colors,
    deterministic,
    distributions,
    noises,
    rotations,
    variation_broadcaster,
)
from composer.variation import math as vmath
from tests import dm_control_wheel
from tests.composer.scenes import Block

PACKAGE = "dm_control_reference"  # dm_control's variation package, renamed
_IMPORTS = (
    ("from dm_control.composer import variation", f"from {PACKAGE} import variation"),
    ("dm_control.composer.variation", f"{PACKAGE}.variation"),
    ("from dm_control.utils import transformations", f"from {PACKAGE} import transformations"),
)


@pytest.fixture(scope="module")
def theirs(tmp_path_factory):
    """A namespace of dm_control's variation modules: theirs.distributions ..."""
    pytest.importorskip("tree")  # dm_control's evaluate uses dm-tree
    root = tmp_path_factory.mktemp("reference")
    package = root / PACKAGE
    (package / "variation").mkdir(parents=True)
    (package / "__init__.py").write_text("")
    with zipfile.ZipFile(dm_control_wheel.wheel()) as archive:
        for name in archive.namelist():
            if name.startswith("dm_control/composer/variation/") and not name.endswith("_test.py"):
                target = package / "variation" / name.rsplit("/", 1)[1]
            elif name == "dm_control/utils/transformations.py":
                target = package / "transformations.py"
            else:
                continue
            source = archive.read(name).decode()
            for old, new in _IMPORTS:
                source = source.replace(old, new)
            target.write_text(source)
    sys.path.insert(0, str(root))
    try:
        modules = {
            name: importlib.import_module(f"{PACKAGE}.variation.{name}")
            for name in (
                "colors",
                "deterministic",
                "distributions",
                "math",
                "noises",
                "rotations",
                "variation_broadcaster",
            )
        }
        modules["variation"] = importlib.import_module(f"{PACKAGE}.variation")
        yield type("Reference", (), modules)
    finally:
        sys.path.remove(str(root))
        for name in [n for n in sys.modules if n.startswith(PACKAGE)]:
            del sys.modules[name]


def same_draws(ours, reference, initial_value=None, current_value=None, calls=5):
    """Call both with the same seeded states `calls` times; the values must be equal, to
    the last bit."""
    mine, their_state = np.random.RandomState(11), np.random.RandomState(11)
    for _ in range(calls):
        a = ours(initial_value, current_value, mine)
        b = reference(initial_value, current_value, their_state)
        np.testing.assert_array_equal(a, b)
        assert np.asarray(a).dtype == np.asarray(b).dtype


SHAPES = [None, 0.0, np.zeros(3), np.zeros((2, 2))]


@pytest.mark.parametrize("initial", SHAPES, ids=["none", "scalar", "3", "2x2"])
@pytest.mark.parametrize(
    ("name", "args", "kwargs"),
    [
        ("Uniform", (), {}),
        ("Uniform", ([0, 1, 2], 5), {}),
        ("UniformInteger", (3, 9), {}),
        ("UniformInteger", (4,), {}),
        ("UniformChoice", (["a", "b", "c"],), {}),
        ("Normal", (1.0, 0.5), {}),
        ("LogNormal", (0.2, 0.3), {}),
        ("Exponential", (2.0,), {}),
        ("Poisson", (3.0,), {}),
        ("Bernoulli", (0.4,), {}),
        ("Uniform", (), {"single_sample": True}),
        ("Normal", (0, 1), {"single_sample": True}),
    ],
)
def test_distributions_match(theirs, name, args, kwargs, initial):
    ours = getattr(distributions, name)(*args, **kwargs)
    reference = getattr(theirs.distributions, name)(*args, **kwargs)
    if name == "Uniform" and args and initial is not None and np.shape(initial) != (3,):
        # Parameters of shape (3,) draw only in their own shape: both refuse.
        with pytest.raises(ValueError):
            ours(initial, None, np.random.RandomState(0))
        with pytest.raises(ValueError):
            reference(initial, None, np.random.RandomState(0))
        return
    same_draws(ours, reference, initial)


def test_varying_parameters_match(theirs):
    def build(module):
        inner = module.Normal(loc=module.Uniform(0, 1), scale=module.Exponential(0.5))
        return module.Uniform(low=inner, high=module.Uniform(2, 3))

    same_draws(build(distributions), build(theirs.distributions), np.zeros(3))


@pytest.mark.parametrize("initial", [None, np.zeros(4)], ids=["none", "4"])
def test_point_on_sphere_and_random_walk_match(theirs, initial):
    for single in (False, True):
        same_draws(
            distributions.UniformPointOnSphere(single),
            theirs.distributions.UniformPointOnSphere(single),
            initial,
        )
    same_draws(
        distributions.BiasedRandomWalk(0.5, 3.0),
        theirs.distributions.BiasedRandomWalk(0.5, 3.0),
        calls=50,
    )


@pytest.mark.filterwarnings("ignore:invalid value encountered in divide:RuntimeWarning")
def test_rotations_match(theirs):
    start = np.array([0.9, 0.1, -0.3, 0.3])
    start /= np.linalg.norm(start)
    module, reference = rotations, theirs.rotations  # (the names the calls below share)
    angle = distributions.Uniform(-np.pi, np.pi, single_sample=True)
    their_angle = theirs.distributions.Uniform(-np.pi, np.pi, single_sample=True)
    axis = distributions.UniformPointOnSphere(single_sample=True)
    their_axis = theirs.distributions.UniformPointOnSphere(single_sample=True)
    same_draws(module.UniformQuaternion(), reference.UniformQuaternion())
    same_draws(
        module.QuaternionFromAxisAngle(axis, angle),
        reference.QuaternionFromAxisAngle(their_axis, their_angle),
        start,
    )
    same_draws(
        module.QuaternionFromAxisAngle((0, 0, 1), 0.0),
        reference.QuaternionFromAxisAngle((0, 0, 1), 0.0),
    )
    for cumulative in (False, True):
        same_draws(
            module.QuaternionPreMultiply(module.UniformQuaternion(), cumulative),
            reference.QuaternionPreMultiply(reference.UniformQuaternion(), cumulative),
            start,
            start[::-1],
        )
        same_draws(
            module.QuaternionRotate(module.UniformQuaternion(), cumulative=cumulative),
            reference.QuaternionRotate(reference.UniformQuaternion(), cumulative=cumulative),
            np.array([1.0, 2.0, 3.0]),
            np.array([-1.0, 0.5, 0.0]),
        )
    same_draws(
        module.QuaternionRotate(start * 2, vec=distributions.Normal(np.zeros(3))),
        reference.QuaternionRotate(start * 2, vec=theirs.distributions.Normal(np.zeros(3))),
    )


def test_noises_colors_math_and_deterministic_match(theirs):
    d, t = distributions, theirs.distributions
    start, now = np.array([1.0, 2.0, 3.0]), np.array([4.0, 5.0, 6.0])
    for cumulative in (False, True):
        same_draws(
            noises.Additive(d.Normal(0, 0.1), cumulative),
            theirs.noises.Additive(t.Normal(0, 0.1), cumulative),
            start,
            now,
        )
        same_draws(
            noises.Multiplicative(d.LogNormal(0, 0.1), cumulative),
            theirs.noises.Multiplicative(t.LogNormal(0, 0.1), cumulative),
            start,
            now,
        )
    same_draws(
        colors.RgbVariation(d.Uniform(), 0.5, d.Uniform(), d.Uniform(0.5, 1)),
        theirs.colors.RgbVariation(t.Uniform(), 0.5, t.Uniform(), t.Uniform(0.5, 1)),
    )
    same_draws(
        colors.HsvVariation(d.Uniform(), d.Uniform(), 0.7),
        theirs.colors.HsvVariation(t.Uniform(), t.Uniform(), 0.7),
    )
    same_draws(colors.GrayVariation(d.Uniform()), theirs.colors.GrayVariation(t.Uniform()))
    for name in ("Log", "Max", "Min", "Norm"):
        same_draws(
            getattr(vmath, name)(d.Uniform([1, 1], [2, 3])),
            getattr(theirs.math, name)(t.Uniform([1, 1], [2, 3])),
        )
    same_draws(
        deterministic.Sequence([1.0, d.Normal(), 3.0]),
        theirs.deterministic.Sequence([1.0, t.Normal(), 3.0]),
        calls=7,
    )
    same_draws(deterministic.Identity(), theirs.deterministic.Identity(), start, now)
    arithmetic = (2 * d.Normal() - d.Uniform()) ** 2 // 0.5 + (-d.Uniform([0, 0, 0], 1))[1:]
    reference = (2 * t.Normal() - t.Uniform()) ** 2 // 0.5 + (-t.Uniform([0, 0, 0], 1))[1:]
    same_draws(arithmetic, reference)


def test_evaluate_of_nested_structures_and_broadcasts_match(theirs):
    d, t = distributions, theirs.distributions

    def structure(module):
        return {"z": module.Normal(), "a": [module.Uniform(), (module.Poisson(), 4)], "m": 1}

    mine, reference = np.random.RandomState(5), np.random.RandomState(5)
    for _ in range(3):
        assert variation.evaluate(structure(d), random_state=mine) == theirs.variation.evaluate(
            structure(t), random_state=reference
        )
    ours = variation_broadcaster.VariationBroadcaster(d.Uniform())
    their = theirs.variation_broadcaster.VariationBroadcaster(t.Uniform())
    proxies = [ours.get_proxy(), ours.get_proxy()]
    their_proxies = [their.get_proxy(), their.get_proxy()]
    mine, reference = np.random.RandomState(6), np.random.RandomState(6)
    for order in ([0, 0, 1, 1], [1, 0, 0, 1, 1, 0]):
        seen = [proxies[i](random_state=mine) for i in order]
        assert seen == [their_proxies[i](random_state=reference) for i in order]


def test_variators_match_on_real_elements(theirs):
    def run(module, dists):
        block = Block()
        block.body.pos = [0.0, 0.0, 0.0]
        variator = module.MJCFVariator()
        variator.bind_attributes(
            block.geom,
            size=dists.Uniform(0.02, 0.05),
            rgba=dists.Uniform([0, 0, 0, 1], [1, 1, 1, 1]),
        )
        variator.bind_attributes(block.body, pos=dists.Normal(0.0, 0.1))
        physics_variator = module.PhysicsVariator()
        physics_variator.bind_attributes(block.body, mass=dists.LogNormal(0.0, 0.2))
        state = np.random.RandomState(9)
        values = []
        for _ in range(3):
            variator.apply_variations(state)
            physics = mjcf.Physics.from_mjcf_model(block.mjcf_model)
            physics_variator.apply_variations(physics, state)
            mass = physics.bind(block.body).mass
            values.append(np.hstack([block.geom.size, block.geom.rgba, block.body.pos, mass]))
            physics_variator.reset_initial_values()  # theirs keeps the first model's otherwise
        return np.array(values)

    np.testing.assert_array_equal(
        run(variation, distributions), run(theirs.variation, theirs.distributions)
    )
