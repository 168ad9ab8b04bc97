# The compiled engine (src/lib.rs). Its functions are private: the package's
# modules wrap them, and the public stubs declare those wrappers.
from typing import Any

__version__: str

class ImuthermError(ValueError): ...

def __getattr__(name: str) -> Any: ...
