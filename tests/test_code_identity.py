"""What counts as other code for a checkpoint (icerubble/code_identity.py):
any statement does; comments, docstrings and layout do not."""
from icerubble.code_identity import python_digest, source_hash

MODULE = '''"""A module."""
import math


def f(x):
    """Twice x."""
    return 2.0 * x  # doubled
'''


def test_comments_docstrings_and_layout_are_not_other_code():
    edited = (MODULE.replace('"""Twice x."""', '"""Two times x, as the paper has it."""')
              .replace("# doubled", "# see eq. 6").replace("2.0 * x", "2.0*x") + "\n\n")
    assert python_digest(edited) == python_digest(MODULE)


def test_any_statement_is_other_code():
    for edit in (("2.0 * x", "2.0 * x + 0.0"), ("2.0", "2.00001"), ("import math", "import cmath")):
        assert python_digest(MODULE.replace(*edit)) != python_digest(MODULE), edit


def test_the_source_hash_is_stable_within_a_process():
    assert source_hash() == source_hash() and len(source_hash()) == 16


def test_the_code_identity_is_taken_as_the_engine_is_loaded():
    # a run's files say which code computed them: taken as the compiled module
    # is loaded, not at its first write, when a rebuild of the checkout during
    # the run may have replaced the module file on disk (a CPU run of
    # 2026-11-30 recorded a later build's hash and commit that way)
    import subprocess
    import sys
    out = subprocess.run([sys.executable, "-c", "import icerubble.engine\n"
                          "from icerubble import code_identity as c\n"
                          "print(c.source_hash.cache_info().currsize, c.code_version.cache_info().currsize)"],
                         capture_output=True, text=True, check=True).stdout.split()
    assert out == ["1", "1"]
