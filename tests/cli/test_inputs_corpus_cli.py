"""The hostile-input corpus (:mod:`ngincompat.studies.corpus`) through the whole command line,
in separate processes (slow tier): a value that segfaults or hangs cannot be seen in-process.

Every numeric parameter of every scene gets every value of the corpus (the hostile values
and the ends of its range); the values the scene accepts run to their end on its preview
preset and quick settings. Asserted: no try ends in a defect (a traceback, a hang, a signal,
a done run with a metric that is not a finite number, another exit code than the
documented 0, 2, 3), and the hostile values that every number refuses are refused.
"""

import pytest

from ngincompat.scenes import SCENES
from ngincompat.studies import corpus

pytestmark = pytest.mark.slow

GROUPS = [(scene, key) for scene, cls in SCENES.items()
          for key in corpus.numeric_parameters(cls)]


@pytest.mark.parametrize("scene, key", GROUPS, ids=[f"{s}-{k}" for s, k in GROUPS])
def test_no_value_of_the_corpus_ends_in_a_defect(scene, key, tmp_path):
    tries = corpus.parameter_tries(scene, key, tmp_path)
    corpus.run_in_one_process(tries)
    defects = [(t.value, t.outcome, t.message) for t in tries if t.outcome in corpus.DEFECTS]
    assert not defects
    refused = {t.value for t in tries if t.outcome == "refused"}
    assert {"1e308", "inf", "-inf", "nan", "two"} <= {v.split(",")[0] for v in refused}
