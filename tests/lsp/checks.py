"""What the pygls-driven end-to-end tests share: failing with a message, and waiting for what the
server sends (diagnostics, progress) with a deadline."""

import asyncio
import sys


def fail(message):
    print(f"FAIL: {message}", file=sys.stderr)
    sys.exit(1)


async def wait_for(predicate, what, timeout=10.0):
    """The first truthy value of `predicate()`, polled until `timeout` seconds have passed."""
    deadline = asyncio.get_running_loop().time() + timeout
    while asyncio.get_running_loop().time() < deadline:
        value = predicate()
        if value:
            return value
        await asyncio.sleep(0.02)
    fail(f"timed out waiting for {what}")
