"""The wall of DESIGN.md: the flight software never imports the truth model
(and the truth model never reads flight-software internals). Checked on the
import statements of every module, so a new module cannot slip past."""
import ast
from pathlib import Path

import pytest

SIM = Path(__file__).parent.parent / "sim"


def _imports(path: Path, root: Path = SIM.parent) -> set[str]:
    names = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            names.update(a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:  # relative: resolve against the package
                pkg = path.parent.relative_to(root).parts
                base = ".".join(pkg[:len(pkg) - node.level + 1] + ((base,) if base else ()))
            names.add(base)
            names.update(f"{base}.{a.name}" for a in node.names)
    return names


@pytest.mark.parametrize("side, forbidden", [("fsw", "sim.truth"), ("truth", "sim.fsw")])
def test_wall(side, forbidden):
    files = sorted((SIM / side).rglob("*.py"))
    assert files, f"no modules under sim/{side}"
    offenders = {str(f.relative_to(SIM)): sorted(i for i in _imports(f) if i == forbidden or i.startswith(forbidden + "."))
                 for f in files}
    assert not {k: v for k, v in offenders.items() if v}


def test_wall_check_sees_a_violation(tmp_path):
    """The checker itself must catch both import forms."""
    bad = tmp_path / "sim" / "fsw" / "probe.py"
    bad.parent.mkdir(parents=True)
    bad.write_text("from sim.truth import plant\nimport sim.truth.rigid_body\nfrom ..truth import wheels\n")
    found = _imports(bad, root=tmp_path)
    assert {"sim.truth", "sim.truth.rigid_body", "sim.truth.wheels"} <= found
