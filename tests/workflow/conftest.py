"""Fixtures shared by the workflow tests: the mesh files of every format read."""

import pytest


@pytest.fixture(scope="module")
def box_files(tmp_path_factory):
    """The two-cube box in every mesh format (:func:`workflow.test_inputs.write_box_files`)."""
    from workflow.test_inputs import write_box_files

    return write_box_files(tmp_path_factory.mktemp("box"))
