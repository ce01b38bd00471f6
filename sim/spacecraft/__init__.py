"""Spacecraft definitions as data files (one YAML per spacecraft) and their loader."""
from __future__ import annotations

import copy
from pathlib import Path

import yaml

from sim.spacecraft.definition import Spacecraft

HERE = Path(__file__).parent


def available() -> list[str]:
    return sorted(p.stem for p in HERE.glob("*.yaml"))


def raw_definition(name: str) -> dict:
    """The spacecraft file as a dict; KeyError names the allowed spacecraft."""
    path = HERE / f"{name}.yaml"
    if name not in available():
        raise KeyError(f"unknown spacecraft {name!r}; allowed: {', '.join(available())}")
    return yaml.safe_load(path.read_text())


def deep_merge(base: dict, overrides: dict) -> dict:
    """A copy of base with overrides applied; nested mappings merge, anything
    else (numbers, lists) replaces."""
    out = copy.deepcopy(base)
    for key, value in overrides.items():
        if isinstance(value, dict) and isinstance(out.get(key), dict):
            out[key] = deep_merge(out[key], value)
        else:
            out[key] = copy.deepcopy(value)
    return out


def load_spacecraft(name: str, overrides: dict | None = None) -> Spacecraft:
    return Spacecraft.model_validate(deep_merge(raw_definition(name), overrides or {}))
