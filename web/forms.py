"""Command forms generated from the command models (sim.commands), so a
command the engine adds appears in the console without console code.

Each field becomes a widget chosen from its JSON schema: numbers, integers,
booleans, choices, 3-vectors; a discriminated union (a fault, a slew target)
becomes a dropdown of its variants followed by the chosen variant's fields;
anything else (quaternions, lists) is a JSON text box. Whatever the widgets
hold is validated by the very model the REST API uses.
"""
from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from pydantic import ValidationError

from sim.commands import COMMAND_ADAPTER, COMMAND_TYPES
from sim.modes import Mode


@dataclass
class FieldSpec:
    name: str
    kind: str          # number | integer | boolean | choice | vector3 | json | union
    initial: Any
    options: tuple = ()
    hint: str = ""
    tag: str = ""                                      # union: the discriminator's name
    variants: dict[str, list] = field(default_factory=dict)   # union: variant -> its FieldSpecs


def _prefill(name: str, schema: dict, frame: dict | None) -> Any:
    """A starting value for a field without a default: the telemetry of the
    same name when there is one (q_RN -> q_RN_w..z), else the schema's minimum,
    else a neutral value."""
    frame = frame or {}
    for axes in (("w", "x", "y", "z"), ("x", "y", "z")):
        names = [f"{name}_{a}" for a in axes]
        if all(n in frame for n in names):
            return [frame[n] for n in names]
    if schema.get("examples"):
        return schema["examples"][0]
    if "minimum" in schema:
        return schema["minimum"]
    if schema.get("type") == "array":
        n = len(schema.get("prefixItems", [])) or schema.get("minItems", 0)
        return [1.0, 0.0, 0.0, 0.0] if n == 4 else [0.0] * n   # four items: a quaternion, identity
    return {"number": 0.0, "integer": 0, "boolean": False, "string": ""}.get(schema.get("type"), None)


def _resolve(prop: dict, defs: dict) -> dict:
    ref = prop.get("$ref", "")
    return defs[ref.split("/")[-1]] if ref.startswith("#/$defs/") else prop


def _spec(name: str, prop: dict, required: set, frame: dict | None, defs: dict) -> FieldSpec:
    hint = prop.get("description", "")
    disc = prop.get("discriminator", {})
    if disc.get("propertyName") and disc.get("mapping"):
        tag = disc["propertyName"]
        variants = {}
        for value, ref in disc["mapping"].items():
            sub = _resolve({"$ref": ref}, defs)
            variants[value] = [_spec(n, _resolve(p, defs), set(sub.get("required", [])), None, defs)
                               for n, p in sub.get("properties", {}).items() if n != tag]
        first = next(iter(variants))
        return FieldSpec(name, "union", first, tuple(variants), hint, tag, variants)
    initial = prop["default"] if "default" in prop else _prefill(name, prop, frame)
    kind = prop.get("type")
    choices = prop.get("enum")
    if choices:
        return FieldSpec(name, "choice", initial if initial in choices else choices[0], tuple(choices), hint)
    if kind in ("number", "integer", "boolean"):
        return FieldSpec(name, kind, initial, (), hint)
    if kind == "array" and len(prop.get("prefixItems", [])) == 3 and isinstance(initial, list):
        return FieldSpec(name, "vector3", tuple(initial), (), hint)
    return FieldSpec(name, "json", json.dumps(initial), (), hint + (" (JSON)" if name in required else ""))


def field_specs(model: type, frame: dict | None = None) -> list[FieldSpec]:
    """The form of one command model."""
    schema = model.model_json_schema()
    required, defs = set(schema.get("required", [])), schema.get("$defs", {})
    return [_spec(name, _resolve(prop, defs), required, frame, defs)
            for name, prop in schema.get("properties", {}).items() if name != "type"]


def add_widget(gui, spec: FieldSpec, label: str | None = None):
    """The viser widget of one (non-union) field."""
    label, hint = label or spec.name, spec.hint or None
    if spec.kind == "number":
        return gui.add_number(label, float(spec.initial or 0.0), step=1e-6, hint=hint)
    if spec.kind == "integer":
        return gui.add_number(label, int(spec.initial or 0), step=1, hint=hint)
    if spec.kind == "boolean":
        return gui.add_checkbox(label, bool(spec.initial), hint=hint)
    if spec.kind == "choice":
        return gui.add_dropdown(label, [str(o) for o in spec.options], initial_value=str(spec.initial), hint=hint)
    if spec.kind == "vector3":
        return gui.add_vector3(label, spec.initial, step=1e-6, hint=hint)
    return gui.add_text(label, spec.initial, hint=hint)


def read_value(spec: FieldSpec, value: Any) -> Any:
    """A widget's value as the model wants it; a union's value is (variant, [its values])."""
    if spec.kind == "union":
        variant, values = value
        return {spec.tag: variant, **{s.name: read_value(s, v) for s, v in zip(spec.variants[variant], values)}}
    if spec.kind == "json":
        try:
            return json.loads(value)
        except json.JSONDecodeError as err:
            raise ValueError(f"{spec.name}: not valid JSON ({err.msg})") from None
    if spec.kind == "vector3":
        return list(value)
    if spec.kind == "choice":
        match = [o for o in spec.options if str(o) == value]
        return match[0] if match else value
    return value


def initial_value(spec: FieldSpec) -> Any:
    if spec.kind == "union":
        return spec.initial, [initial_value(s) for s in spec.variants[spec.initial]]
    return spec.initial


def build_command(type_name: str, specs: list[FieldSpec], values: list[Any]):
    """The command object, or ValueError with a message naming the field."""
    data = {"type": type_name}
    for spec, value in zip(specs, values):
        data[spec.name] = read_value(spec, value)
    try:
        return COMMAND_ADAPTER.validate_python(data)
    except ValidationError as err:
        lines = []
        for e in err.errors(include_url=False):
            loc = ".".join(str(p) for p in e["loc"] if p not in COMMAND_TYPES)
            lines.append(f"{loc}: {e['msg'].removeprefix('Value error, ')}" if loc else e["msg"])
        raise ValueError("; ".join(lines)) from None


class _UnionWidget:
    """A variant dropdown and the chosen variant's fields, rebuilt on change."""

    def __init__(self, gui, spec: FieldSpec):
        self.gui, self.spec = gui, spec
        self.choice = gui.add_dropdown(spec.name, list(spec.options), initial_value=spec.initial,
                                       hint=spec.hint or None)
        self.folder = gui.add_folder(f"{spec.name} fields")
        self.widgets: list = []
        self._fill()
        self.choice.on_update(lambda _: self._fill())

    def _fill(self) -> None:
        for w in self.widgets:
            w.remove()
        with self.folder:
            self.widgets = [add_widget(self.gui, s, f"{self.spec.name}.{s.name}")
                            for s in self.spec.variants[self.choice.value]]

    @property
    def value(self):
        return self.choice.value, [w.value for w in self.widgets]

    def remove(self) -> None:
        self.choice.remove()
        self.folder.remove()


class CommandForm:
    """One client's form for one command type, inside a container."""

    def __init__(self, gui, type_name: str, frame: dict | None, on_send: Callable[[str, Any], None]):
        self.type_name = type_name
        model = COMMAND_TYPES[type_name]
        self.specs = field_specs(model, frame)
        doc = (model.__doc__ or "").strip().split("\n\n")[0].replace("\n", " ")
        hazard = " **Hazardous: asks for confirmation.**" if model.hazardous else ""
        legal = "any mode" if set(model.legal_modes) == set(Mode) else ", ".join(m.name for m in model.legal_modes)
        self.handles = [gui.add_markdown(f"{doc}{hazard}  \nLegal in: {legal or 'no mode yet'}")]
        self.widgets = [_UnionWidget(gui, s) if s.kind == "union" else add_widget(gui, s) for s in self.specs]
        self.handles.extend(self.widgets)
        send = gui.add_button("Send", color="red" if model.hazardous else "blue")
        self.handles.append(send)
        send.on_click(lambda _: on_send(type_name, self))

    def command(self):
        return build_command(self.type_name, self.specs, [w.value for w in self.widgets])

    def remove(self) -> None:
        for h in self.handles:
            h.remove()
        self.handles.clear()
