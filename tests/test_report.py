import json

import numpy as np
import pytest

from tentaclass.errors import InputError
from tentaclass.report import classification_table, table_to_json


def test_table_columns_and_json():
    t = classification_table(np.array(["a", "b"]), [[0.9, 0.1], [0.3, 0.7]], np.array(["a", "b"]))
    assert t["probability"].tolist() == [0.9, 0.7] and t["p_b"].tolist() == [0.1, 0.7]
    assert json.loads(table_to_json(t))[1] == {
        "index": 1, "label": "b", "probability": 0.7, "p_a": 0.3, "p_b": 0.7
    }  # fmt: skip
    empty = classification_table(np.zeros(0, str), np.zeros((0, 2)), np.array(["a", "b"]))
    assert all(len(v) == 0 for v in empty.values()) and empty["p_a"].dtype == np.float64


@pytest.mark.parametrize("proba", [np.zeros((3, 2)), np.zeros((2, 3)), np.zeros(4)])
def test_probabilities_of_another_shape_are_refused(proba):
    # (3, 2) for 2 labels was numpy's "cannot reshape array of size 6 into shape (2,2)"
    with pytest.raises(
        InputError, match=r"^proba must have shape \(n_samples, n_classes\) = \(2, 2\)"
    ):
        classification_table(np.array(["a", "b"]), proba, np.array(["a", "b"]))
