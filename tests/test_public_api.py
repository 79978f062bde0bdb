"""The framework's public API is one import: every name ``abm.__all__`` states resolves to the
object its module defines, and ``import abm.errors`` (the command line's first import) does not
load the simulation modules."""

import subprocess
import sys

import pytest

import abm


@pytest.mark.parametrize("name", abm.__all__)
def test_every_public_name_is_its_modules_object(name):
    value = getattr(abm, name)
    module = sys.modules[abm._WHERE[name]]
    assert value is getattr(module, name)


def test_an_unknown_name_is_an_attribute_error():
    with pytest.raises(AttributeError, match="no attribute 'Swarm'"):
        abm.Swarm  # noqa: B018


def test_importing_the_errors_loads_no_simulation_module():
    code = "import sys, abm.errors; print(sorted(m for m in sys.modules if m.startswith('abm')))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "['abm', 'abm.errors']"


def test_the_stated_api_is_exactly_the_names_with_a_home():
    assert sorted(abm.__all__) == sorted(abm._WHERE)
