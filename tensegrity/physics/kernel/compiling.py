"""How the kernel (`kernel/`) is compiled and cached by numba: `jit` (numba's cache, watching every
source file the kernel is compiled from), `stack_array` (working arrays on the stack) and
`callees_first` (cached code that runs the same machine code as freshly compiled code)."""
from __future__ import annotations

import hashlib
from collections.abc import Callable, Iterable, Sequence
from pathlib import Path

import llvmlite.ir as llir
import numba as nb
import numpy as np
from numba.core import caching, cgutils, types
from numba.core.dispatcher import Dispatcher
from numba.extending import intrinsic

# The files compiled into the kernel's functions besides their own: the other files of the
# kernel folder and the actuator's law (physics/actuator.py). numba's stamp covers only a
# function's own file: a cached function would link the stale cached code of a changed callee
# in another file.
WATCHED = sorted(p for p in Path(__file__).parent.glob("*.py") if p.name != "__init__.py")
WATCHED.append(Path(__file__).parents[1] / "actuator.py")


def _watching(locator):
    """numba's cache locator class `locator`, with a source stamp that also covers WATCHED:
    numba would only watch the file of the function it compiles and load stale code."""
    class Locator(locator):
        def get_source_stamp(self):
            return super().get_source_stamp(), *(hashlib.sha256(p.read_bytes()).digest()
                                                for p in WATCHED)
    Locator.__name__ = Locator.__qualname__ = locator.__name__
    return Locator


class _CacheImpl(caching.CompileResultCacheImpl):
    _locator_classes = [_watching(c) for c in caching.CompileResultCacheImpl._locator_classes]


class _Cache(caching.FunctionCache):
    _impl_class = _CacheImpl


def jit(**options: object) -> Callable[[Callable], Dispatcher]:
    """nb.njit(**options) (kernel.stages.JIT, INLINE or EXACT), cached by `_Cache`: every
    compiled function of the kernel folder."""
    def wrap(f):
        d = nb.njit(**{**options, "cache": False})(f)
        d._cache = _Cache(d.py_func)
        return d
    return wrap


def stack_array(*shape: int) -> Callable:
    """A compiled function () -> an uninitialised C-contiguous float64 array of `shape` on the
    stack of the function that calls it. Unlike a heap array, LLVM knows that it overlaps no
    other array, which lets it vectorise the lane loops. It must not outlive that call."""
    arrty = types.Array(types.float64, len(shape), "C")

    @intrinsic
    def make(typingctx):
        def codegen(context, builder, sig, args):
            f8 = context.get_data_type(types.float64)
            block = cgutils.alloca_once(builder, llir.ArrayType(f8, int(np.prod(shape))))
            block.align = 64  # a cache line: whole-register loads never straddle two
            data = builder.bitcast(block, f8.as_pointer())
            strides = [8 * int(np.prod(shape[k + 1:])) for k in range(len(shape))]
            ary = context.make_array(arrty)(context, builder)
            intp = lambda n: context.get_constant(types.intp, n)  # noqa: E731
            context.populate_array(ary, data=data, shape=[intp(n) for n in shape], itemsize=intp(8),
                                   strides=[intp(s) for s in strides], meminfo=None)
            return ary._getvalue()
        return arrty(), codegen
    return make


def callees_first(caller: Dispatcher, callees: Iterable[Dispatcher], args: Sequence,
                  lead: Iterable[types.Type] = (types.int64, types.uint64)) -> Dispatcher:
    """`caller` (a dispatcher), after compiling or loading from the cache each of `callees` for
    the types of (an index of a type in `lead`,) + `args` (how `caller` calls them; a prange index
    is int64 or uint64). Returns `caller`.

    Why: numba compiles a callee on its own, then links a copy of its optimised code into the
    caller and optimises it once more. A fresh process runs the callee's own code (the caller's
    call resolves by name to the first definition loaded), but cached code loaded alone runs
    the twice-optimised copy, which is slower (about 20 % for a robot alone). Loaded first, the
    callee's own code is what the cached caller calls as well."""
    sig = tuple(caller.typeof_pyval(a) for a in args)
    for callee in callees:
        for t in lead:
            callee.compile((t,) + sig)
    return caller
