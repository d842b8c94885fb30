"""Thin routers: parse, call the core or the store, return a schema."""
