"""What a message suggests for a name mjcf does not know: the closest known name
(`suggest`), or, for a child an element cannot have, what replaces an element MuJoCo
removed (`suggest_child`)."""

from __future__ import annotations

from collections.abc import Iterable

from mjcf import errors


def suggest(word: str, choices: Iterable[str]) -> str:
    """' (did you mean 'x'?)' for the closest choice, or ''."""
    return errors.did_you_mean(word, choices, n=1)


# Elements older MuJoCo had (dm_control's schema still has them), with what replaces them.
_REMOVED_ELEMENTS = {
    "composite": "MuJoCo 4 has no <composite>: build the object with <flexcomp> (cables, "
    "cloth, soft bodies), or with bodies (nested for a chain, <replicate> for copies)",
}


def suggest_child(tag: str, allowed: Iterable[str]) -> str:
    """What to say of child `tag` an element cannot have: what replaces an element
    MuJoCo removed, else the closest allowed tag (see `suggest`)."""
    removed = _REMOVED_ELEMENTS.get(tag)
    return f" ({removed})" if removed else suggest(tag, allowed)
