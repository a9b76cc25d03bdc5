-- | stref: executable reference semantics of IEC 61131-3 Structured Text.
module Stref (version) where

version :: String
version = "0.1.0"
