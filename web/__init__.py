"""The viser operations console (see the console issue); talks to the
service, never to sim internals."""
