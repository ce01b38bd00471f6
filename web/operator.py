"""One client's operator panel: locked until that client enters the operator
token; then pacing, command forms (generated from the command models),
alarm acknowledgement and run loading. Hazardous commands and replacing the
live run ask for confirmation in a modal.

Callbacks run on viser's worker threads and reach the simulation only through
the service's thread-safe calls.
"""
from __future__ import annotations

import logging
import secrets
from pathlib import Path

from server.pacing import WARPS
from server.service import load_live_scenario
from sim.commands import COMMAND_TYPES
from sim.scenario import ScenarioError
from web.forms import CommandForm

log = logging.getLogger("acs.console")
WARP_LABELS = {0: "Pause", 1: "1×", 10: "10×", 100: "100×", 1000: "1000×", "max": "max"}


class OperatorPanel:
    def __init__(self, client, service, token: str, container, scenario_dir: Path):
        self.client, self.service, self.token = client, service, token
        self.container, self.scenario_dir = container, scenario_dir
        self.who = f"console:{client.client_id}"
        self.handles: list = []
        self.form: CommandForm | None = None
        self._locked_view()

    def _clear(self) -> None:
        for h in self.handles:
            h.remove()
        self.handles.clear()
        self.form = None

    def _notify(self, title: str, body: str, color: str = "red") -> None:
        self.client.add_notification(title, body, auto_close_seconds=6.0, color=color)

    # -- locked -----------------------------------------------------------------------------
    def _locked_view(self) -> None:
        self._clear()
        gui = self.client.gui
        with self.container:
            md = gui.add_markdown("**Locked.** Commanding is locked. Enter the operator token (printed by `acs serve`, "
                                  "or ACS_TOKEN).")
            field = gui.add_text("Operator token", "")
            button = gui.add_button("Unlock", icon=None)
        self.handles += [md, field, button]

        @button.on_click
        def _(event) -> None:
            entered = field.value
            field.value = ""      # the token never stays in the GUI state
            if secrets.compare_digest(entered.strip().encode(), self.token.encode()):
                self._unlocked_view()
            else:
                self._notify("Wrong token", "Commanding stays locked.")

    # -- unlocked -----------------------------------------------------------------------------
    def _unlocked_view(self) -> None:
        self._clear()
        gui = self.client.gui
        with self.container:
            self.handles.append(gui.add_markdown("**Unlocked** for this browser tab."))
            pace = gui.add_button_group("Warp", [WARP_LABELS[w] for w in WARPS])
            step = gui.add_button("Step one cycle (paused)")
            kinds = list(COMMAND_TYPES)
            chooser = gui.add_dropdown("Command", kinds, initial_value=kinds[0])
            self.form_folder = gui.add_folder("Command form")
            ack = gui.add_button("Acknowledge all alarms")
            scenarios = sorted(p.stem for p in self.scenario_dir.glob("*.yaml")) or ["live_sdo"]
            run_pick = gui.add_dropdown("Scenario", scenarios, initial_value=scenarios[0])
            load = gui.add_button("Load as new run")
            lock = gui.add_button("Lock")
        self.handles += [pace, step, chooser, self.form_folder, ack, run_pick, load, lock]
        self._show_form(chooser.value)

        @pace.on_click
        def _(event) -> None:
            warp = next(w for w, label in WARP_LABELS.items() if label == event.target.value)
            self._guard(lambda: self.service.set_warp(warp, self.who))

        @step.on_click
        def _(event) -> None:
            self._guard(lambda: self.service.step(1, self.who))

        @chooser.on_update
        def _(event) -> None:
            self._show_form(chooser.value)

        @ack.on_click
        def _(event) -> None:
            for alarm in self.service.run.limits.alarms():
                if not alarm["acknowledged"]:
                    self._guard(lambda a=alarm: self.service.acknowledge(a["id"], self.who))

        @load.on_click
        def _(event) -> None:
            name = run_pick.value
            self._confirm(f"Replace the live run with {name}?", "The live run stops and stays in the archive.",
                          lambda: self._load(name))

        @lock.on_click
        def _(event) -> None:
            self._locked_view()

    def _show_form(self, type_name: str) -> None:
        if self.form is not None:
            self.form.remove()
        with self.form_folder:
            self.form = CommandForm(self.client.gui, type_name, self.service.hub.latest, self._send)

    def _send(self, type_name: str, form: CommandForm) -> None:
        try:
            command = form.command()
        except ValueError as err:
            self._notify(f"{type_name}: not sent", str(err))
            return
        if type(command).hazardous:
            self._confirm(f"Send hazardous command {type_name}?", f"Arguments: {command.model_dump(exclude={'type'})}",
                          lambda: self._submit(command))
        else:
            self._submit(command)

    def _submit(self, command) -> None:
        snap = self._guard(lambda: self.service.submit(command, self.who))
        if snap is not None:
            self._notify(f"Command {snap['id']} queued", f"{snap['type']}: watch its lifecycle in Commands.",
                         color="green")

    def _load(self, name: str) -> None:
        try:
            scenario, sc = load_live_scenario(self.scenario_dir / f"{name}.yaml")
        except ScenarioError as err:
            self._notify("Scenario not loaded", str(err))
            return
        self._guard(lambda: self.service.load(scenario, sc, None, self.who))

    def _confirm(self, title: str, body: str, action) -> None:
        gui = self.client.gui
        with gui.add_modal(title) as modal:
            gui.add_markdown(body)
            yes = gui.add_button("Confirm", color="red")
            no = gui.add_button("Cancel")

        @yes.on_click
        def _(event) -> None:
            modal.close()
            action()

        @no.on_click
        def _(event) -> None:
            modal.close()

    def _guard(self, call):
        """Run a service call; its refusal becomes a notification, never a crash."""
        try:
            return call()
        except Exception as err:   # anything the service refuses must not kill the GUI thread
            log.info("console request refused: %s", err)
            self._notify("Refused", str(err) or type(err).__name__)
            return None
