import pytest


@pytest.fixture(scope="session")
def recognizer():
    from tentaclass.web import Recognizer

    return Recognizer()
