"""Command forms generated from the command models (sim.commands), so a
command the engine adds appears in the console without console code.

Each field becomes a widget chosen from its JSON schema: numbers, integers,
booleans, choices, 3-vectors; anything else (quaternions, nested targets,
lists) is a JSON text box. Whatever the widgets hold is validated by the very
model the REST API uses.
"""
from __future__ import annotations

import json
from dataclasses import dataclass
from typing import Any, Callable

from pydantic import ValidationError

from sim.commands import COMMAND_ADAPTER, COMMAND_TYPES


@dataclass
class FieldSpec:
    name: str
    kind: str          # number | integer | boolean | choice | vector3 | json
    initial: Any
    options: tuple = ()
    hint: str = ""


def _prefill(name: str, schema: dict, frame: dict | None) -> Any:
    """A starting value for a field without a default: the telemetry of the
    same name when there is one (q_RN -> q_RN_w..z), else a neutral value."""
    frame = frame or {}
    for axes in (("w", "x", "y", "z"), ("x", "y", "z")):
        names = [f"{name}_{a}" for a in axes]
        if all(n in frame for n in names):
            return [frame[n] for n in names]
    if schema.get("type") == "array":
        n = len(schema.get("prefixItems", [])) or schema.get("minItems", 0)
        return [0.0] * n
    return {"number": 0.0, "integer": 0, "boolean": False, "string": ""}.get(schema.get("type"), None)


def field_specs(model: type, frame: dict | None = None) -> list[FieldSpec]:
    """The form of one command model."""
    schema = model.model_json_schema()
    required = set(schema.get("required", []))
    specs = []
    for name, prop in schema.get("properties", {}).items():
        if name == "type":
            continue
        initial = prop["default"] if "default" in prop else _prefill(name, prop, frame)
        hint = prop.get("description", "")
        kind = prop.get("type")
        choices = prop.get("enum")
        if choices:
            specs.append(FieldSpec(name, "choice", initial if initial in choices else choices[0], tuple(choices),
                                   hint))
        elif kind in ("number", "integer", "boolean"):
            specs.append(FieldSpec(name, kind, initial, (), hint))
        elif kind == "array" and len(prop.get("prefixItems", [])) == 3 and isinstance(initial, list):
            specs.append(FieldSpec(name, "vector3", tuple(initial), (), hint))
        else:
            specs.append(FieldSpec(name, "json", json.dumps(initial), (),
                                   hint + ("" if name not in required else " (required; JSON)")))
    return specs


def add_widget(gui, spec: FieldSpec):
    """The viser widget of one field."""
    if spec.kind == "number":
        return gui.add_number(spec.name, float(spec.initial or 0.0), step=1e-6, hint=spec.hint or None)
    if spec.kind == "integer":
        return gui.add_number(spec.name, int(spec.initial or 0), step=1, hint=spec.hint or None)
    if spec.kind == "boolean":
        return gui.add_checkbox(spec.name, bool(spec.initial), hint=spec.hint or None)
    if spec.kind == "choice":
        return gui.add_dropdown(spec.name, [str(o) for o in spec.options], initial_value=str(spec.initial),
                                hint=spec.hint or None)
    if spec.kind == "vector3":
        return gui.add_vector3(spec.name, spec.initial, step=1e-6, hint=spec.hint or None)
    return gui.add_text(spec.name, spec.initial, hint=spec.hint or None)


def read_value(spec: FieldSpec, value: Any) -> Any:
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


class CommandForm:
    """One client's form for one command type, inside a container."""

    def __init__(self, gui, type_name: str, frame: dict | None, on_send: Callable[[str, Any], None]):
        self.type_name = type_name
        model = COMMAND_TYPES[type_name]
        self.specs = field_specs(model, frame)
        self.handles = []
        doc = (model.__doc__ or "").strip().split("\n\n")[0].replace("\n", " ")
        hazard = " **Hazardous: asks for confirmation.**" if model.hazardous else ""
        legal = ", ".join(m.name for m in model.legal_modes)
        self.handles.append(gui.add_markdown(f"{doc}{hazard}  \nLegal in: {legal or 'any mode'}"))
        self.widgets = [add_widget(gui, s) for s in self.specs]
        self.handles.extend(self.widgets)
        send = gui.add_button("Send", color="red" if model.hazardous else "blue", icon=None)
        self.handles.append(send)

        @send.on_click
        def _(event) -> None:
            on_send(type_name, self)

    def command(self):
        return build_command(self.type_name, self.specs, [w.value for w in self.widgets])

    def remove(self) -> None:
        for h in self.handles:
            h.remove()
        self.handles.clear()
