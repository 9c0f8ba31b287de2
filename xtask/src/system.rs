//! System packages the tasks need.
