"""docs/modes.md tied to sim/modes.py and to the seed text (seed 001 "Attitude
control modes" and the mode sections; seed 000 for the integrator).

* The doc's table and its mermaid diagram are ALLOWED, edge for edge and cause
  for cause.
* Every quotation in the doc (outside code blocks) occurs verbatim (whitespace
  normalised) in the seed, and in the seed section it names; rows without a
  quotation must be marked **choice**.
* Facts the seed states about the transitions hold in ALLOWED.
* refusal() explains an illegal pair by naming the reachable modes.
"""
import os
import re
from pathlib import Path

import pytest

from sim.modes import ALLOWED, AUTONOMOUS, CAUSES, FDC, GROUND, Mode, refusal

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "modes.md"
# copies of the two seeds (NASA GSFC papers) live with the tests, so a fresh
# clone checks every quote; SDO_SEEDS_DIR points at another copy
SEEDS = Path(os.environ.get("SDO_SEEDS_DIR", Path(__file__).parent / "data" / "seeds"))
SEED_001 = SEEDS / "001_0d348d12093e1d79.txt"
SEED_000 = SEEDS / "000_24d60e6d328bcd52.txt"

M = Mode
MAIN_PROCESSOR = (M.SUNACQ, M.INERTIAL, M.SCIENCE, M.DELTAH, M.DELTAV)
QUOTE_RE = re.compile(r'"([^"]+)"(?:\s*\(([^)]+)\))?')


def _norm(text: str) -> str:
    return " ".join(text.split())


def _doc() -> str:
    return DOC.read_text(encoding="utf-8")


def _prose(doc: str) -> str:
    """The doc without its fenced code blocks (the mermaid diagram)."""
    return re.sub(r"```.*?```", "", doc, flags=re.S)


def _table_rows(doc: str) -> list[tuple[Mode, Mode, tuple[str, ...], str]]:
    rows, in_table = [], False
    for line in doc.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")] if line.startswith("|") else None
        if cells and [c.lower() for c in cells[:3]] == ["from", "to", "causes"]:
            in_table = True
            continue
        if not in_table:
            continue
        if cells is None:
            break
        if set(cells[0]) <= set("-: "):
            continue
        assert len(cells) == 4, f"table row needs 4 cells: {line}"
        causes = tuple(c.strip() for c in cells[2].split(","))
        rows.append((Mode[cells[0]], Mode[cells[1]], causes, cells[3]))
    return rows


def _mermaid_edges(doc: str) -> dict[tuple[Mode, Mode], tuple[str, ...]]:
    block = re.search(r"```mermaid\n(.*?)```", doc, flags=re.S)
    assert block and "stateDiagram-v2" in block.group(1)
    edges = {}
    for m in re.finditer(r"^\s*(\w+)\s*-->\s*(\w+)\s*:\s*(.+)$", block.group(1), flags=re.M):
        key = (Mode[m.group(1)], Mode[m.group(2)])
        assert key not in edges, f"edge drawn twice: {key}"
        edges[key] = tuple(c.strip() for c in m.group(3).split(","))
    return edges


def _seed_sections() -> dict[str, str]:
    """Seed 001 split at its markdown headings: normalised heading -> normalised text."""
    sections, name, lines = {}, "", []
    for line in SEED_001.read_text(encoding="utf-8").splitlines():
        if line.startswith("#"):
            sections[name] = _norm("\n".join(lines))
            name, lines = line.strip("#* ").lower(), []
        else:
            lines.append(line)
    sections[name] = _norm("\n".join(lines))
    return sections


@pytest.fixture(scope="module")
def seeds():
    return _seed_sections(), _norm(SEED_001.read_text(encoding="utf-8")), _norm(SEED_000.read_text(encoding="utf-8"))


def _occurs(quote: str, text: str) -> bool:
    """Verbatim, whitespace-normalised; ' ... ' separates fragments that must occur in order."""
    pos = 0
    for frag in _norm(quote).split(" ... "):
        pos = text.find(frag.strip(), pos)
        if pos < 0:
            return False
        pos += len(frag)
    return True


# -- the table is ALLOWED -------------------------------------------------------

def test_table_is_allowed_edge_for_edge():
    rows = _table_rows(_doc())
    table = {}
    for f, t, causes, _ in rows:
        assert (f, t) not in table, f"{f.name} -> {t.name} listed twice"
        assert set(causes) <= set(CAUSES), f"{f.name} -> {t.name}: unknown cause in {causes}"
        table[(f, t)] = causes
    assert set(table) == set(ALLOWED), (
        f"in doc only: {sorted((f.name, t.name) for f, t in set(table) - set(ALLOWED))}; "
        f"in ALLOWED only: {sorted((f.name, t.name) for f, t in set(ALLOWED) - set(table))}")
    for key, causes in ALLOWED.items():
        assert set(table[key]) == set(causes), f"{key[0].name} -> {key[1].name}: doc {table[key]}, ALLOWED {causes}"


def test_mermaid_diagram_is_allowed():
    edges = _mermaid_edges(_doc())
    assert set(edges) == set(ALLOWED)
    for key, causes in ALLOWED.items():
        assert set(edges[key]) == set(causes), f"{key[0].name} -> {key[1].name}"


def test_every_row_is_quoted_or_marked_choice():
    for f, t, _, basis in _table_rows(_doc()):
        assert QUOTE_RE.search(basis) or "**choice**" in basis, f"{f.name} -> {t.name}: no quote and no choice"


def test_rows_the_seed_states_are_not_marked_choice():
    """The edges the seed spells out with their causes carry quotes only."""
    stated = {(M.INERTIAL, M.SCIENCE), (M.SCIENCE, M.SUNACQ), (M.SCIENCE, M.SAFEHOLD), (M.INERTIAL, M.DELTAV)}
    for f, t, _, basis in _table_rows(_doc()):
        if (f, t) in stated:
            assert "choice" not in basis and QUOTE_RE.search(basis), f"{f.name} -> {t.name}"


# -- the quotations are the seed's ------------------------------------------------

def test_quotes_are_balanced():
    for n, line in enumerate(_prose(_doc()).splitlines(), 1):
        assert line.count('"') % 2 == 0, f"unbalanced quote on line {n}: {line}"


def test_every_quote_occurs_verbatim_in_the_named_seed_section(seeds):
    sections, seed001, seed000 = seeds
    quotes = QUOTE_RE.findall(_prose(_doc()))
    assert len(quotes) >= 20
    for quote, section in quotes:
        if section.strip().lower() == "seed 000":
            assert _occurs(quote, seed000), f"not in seed 000: {quote!r}"
        elif section:
            name = section.strip().lower()
            assert name in sections, f"no section {section!r} in seed 001 (have {sorted(sections)})"
            assert _occurs(quote, sections[name]), f"not in seed 001 section {section!r}: {quote!r}"
        else:
            assert _occurs(quote, seed001), f"not in seed 001: {quote!r}"


def test_quote_checker_rejects_a_paraphrase(seeds):
    """ALLOWED's comment paraphrases Safehold entry; the seed has no such sentence."""
    _, seed001, _ = seeds
    assert not _occurs("from any mode by FDC or ground", seed001)
    assert _occurs("FDC or ground can command the spacecraft from Science mode to Sun Acquisition or Safehold", seed001)


# -- facts the seed states --------------------------------------------------------

def _exits(mode, cause=None):
    return {t for (f, t), c in ALLOWED.items() if f == mode and (cause is None or cause in c)}


def _entries(mode, cause=None):
    return {f for (f, t), c in ALLOWED.items() if t == mode and (cause is None or cause in c)}


def test_deltav_entry_is_strictly_ground_commanded_from_inertial():
    # "The transition between Inertial and DeltaV mode is strictly ground commanded"
    assert ALLOWED[(M.INERTIAL, M.DELTAV)] == (GROUND,)
    assert _entries(M.DELTAV) == {M.INERTIAL}


def test_deltav_returns_to_inertial_autonomously_or_by_command():
    # "the transition back to Inertial mode is autonomously enforced, but may be commanded if necessary"
    assert {GROUND, AUTONOMOUS} <= set(ALLOWED[(M.DELTAV, M.INERTIAL)])
    assert _exits(M.DELTAV, AUTONOMOUS) == {M.INERTIAL}


def test_every_other_main_processor_mode_can_enter_inertial():
    # "All of the other main processor modes have the capability to enter this mode"
    assert _entries(M.INERTIAL) == {M.SUNACQ, M.SCIENCE, M.DELTAH, M.DELTAV}


def test_every_mode_can_be_sent_to_safehold_by_ground_and_fdc():
    # stated for Science; for the other modes a choice (docs/modes.md)
    for m in MAIN_PROCESSOR:
        assert {GROUND, FDC} <= set(ALLOWED[(m, M.SAFEHOLD)]), m.name
    assert AUTONOMOUS not in {c for (f, t), cs in ALLOWED.items() if M.SAFEHOLD in (f, t) for c in cs}


def test_science_exits_are_inertial_sunacq_safehold():
    # "Transitions into and out of Science mode are nominally via Inertial mode. The only exception is
    # that FDC or ground can command the spacecraft from Science mode to Sun Acquisition or Safehold."
    assert _exits(M.SCIENCE) == {M.INERTIAL, M.SUNACQ, M.SAFEHOLD}
    assert set(ALLOWED[(M.SCIENCE, M.SUNACQ)]) == set(ALLOWED[(M.SCIENCE, M.SAFEHOLD)]) == {GROUND, FDC}
    assert _entries(M.SCIENCE) == {M.INERTIAL}


def test_inertial_to_science_is_autonomous():
    # "the software automatically transitions from Inertial mode into Science mode"
    assert AUTONOMOUS in ALLOWED[(M.INERTIAL, M.SCIENCE)]


def test_deltah_autonomous_exits_are_its_entry_modes():
    # "the mode exits to the mode from which it was entered"
    assert _exits(M.DELTAH, AUTONOMOUS) == _entries(M.DELTAH) == {M.SUNACQ, M.INERTIAL}


def test_thruster_modes_are_entered_only_by_ground():
    for target in (M.DELTAV, M.DELTAH):
        for f in _entries(target):
            assert ALLOWED[(f, target)] == (GROUND,), f"{f.name} -> {target.name}"
    assert (M.SCIENCE, M.DELTAV) not in ALLOWED and (M.SCIENCE, M.DELTAH) not in ALLOWED


def test_autonomous_transitions_may_be_commanded_directly():
    # "Certain transitions are labeled as autonomous; ... but the transitions may be commanded directly as well."
    for key, causes in ALLOWED.items():
        if AUTONOMOUS in causes:
            assert GROUND in causes, f"{key[0].name} -> {key[1].name}"


def test_no_self_loops():
    assert all(f != t for f, t in ALLOWED)


# -- refusal() --------------------------------------------------------------------

def test_refusal_names_the_allowed_targets_for_an_illegal_pair():
    for f in Mode:
        for t in Mode:
            if f == t or (f, t) in ALLOWED:
                continue
            reason = refusal(f, t, GROUND)
            assert "not an allowed transition" in reason and f.name in reason and t.name in reason
            listed = reason.split(f"from {f.name}:", 1)[1]
            assert {n.strip() for n in listed.split(",")} == {m.name for m in _exits(f)}, reason


def test_refusal_is_empty_for_every_legal_pair_and_cause():
    for (f, t), causes in ALLOWED.items():
        for cause in causes:
            assert refusal(f, t, cause) == "", f"{f.name} -> {t.name} by {cause}"


def test_refusal_of_a_legal_pair_by_the_wrong_cause():
    reason = refusal(M.INERTIAL, M.DELTAV, FDC)
    assert reason and "ground" in reason and "fdc" in reason
    science_to_deltav = refusal(M.SCIENCE, M.DELTAV, GROUND)
    assert all(m in science_to_deltav for m in ("INERTIAL", "SUNACQ", "SAFEHOLD"))
    assert refusal(M.SCIENCE, M.SCIENCE, GROUND) == "already in SCIENCE"
