"""The robot's chest tablet and the live view of its mind, served as web pages (starlette
on uvicorn): ``companion tablet``, ``companion run --tablet`` and ``companion view``
(docs/tablet.md)."""
