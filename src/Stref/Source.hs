-- | Turning the bytes of a source file into text. A file must be UTF-8 (plain
-- ASCII is UTF-8); anything else is refused with the place of the first bad
-- byte rather than silently replaced, so that a line and column reported
-- later always point at what the user wrote.
module Stref.Source
  ( decodeSource
  , EncodingError (..)
  , renderEncodingError
  , firstInvalidUtf8
  ) where

import qualified Data.ByteString as BS
import Data.ByteString (ByteString)
import Data.Text (Text)
import qualified Data.Text as T
import qualified Data.Text.Encoding as TE
import Data.Word (Word8)

-- | Where the bytes stop being UTF-8.
data EncodingError = EncodingError
  { eeOffset :: !Int -- ^ 0-based byte offset of the first invalid byte
  , eeLine :: !Int -- ^ 1-based
  , eeColumn :: !Int -- ^ 1-based, in characters
  , eeByte :: !Word8
  }
  deriving (Eq, Show)

-- | Decode a source file. A leading byte order mark is dropped (editors on
-- Windows write one); it is not part of the program.
decodeSource :: ByteString -> Either EncodingError Text
decodeSource bytes0 = case TE.decodeUtf8' bytes of
  Right t -> Right t
  Left _ ->
    let off = maybe 0 id (firstInvalidUtf8 bytes)
        before = TE.decodeUtf8 (BS.take off bytes) -- valid by construction
        line = 1 + T.count "\n" before
        column = 1 + T.length (T.takeWhileEnd (/= '\n') before)
        byte = if off < BS.length bytes then BS.index bytes off else 0
     in Left (EncodingError (off + bomLength) line column byte)
  where
    bom = BS.pack [0xEF, 0xBB, 0xBF]
    (bytes, bomLength)
      | bom `BS.isPrefixOf` bytes0 = (BS.drop 3 bytes0, 3)
      | otherwise = (bytes0, 0)

-- | @file:line:col: error: ...@, in the form of the other verification errors.
renderEncodingError :: FilePath -> EncodingError -> Text
renderEncodingError file (EncodingError off l c b) =
  T.pack file <> ":" <> tshow l <> ":" <> tshow c
    <> ": error: the file is not valid UTF-8 text (byte "
    <> hexByte b
    <> " at byte offset "
    <> tshow off
    <> "); save it as UTF-8 or plain ASCII [invalid-encoding]\n"
  where
    tshow :: Int -> Text
    tshow = T.pack . show
    hexByte w = "16#" <> T.pack [digit (w `div` 16), digit (w `mod` 16)]
    digit d = "0123456789ABCDEF" !! fromIntegral d

-- | The offset of the first byte that does not belong to a well-formed UTF-8
-- sequence (Unicode Table 3-7: no overlong forms, no surrogates, nothing
-- above U+10FFFF), or Nothing if the whole string is well formed.
firstInvalidUtf8 :: ByteString -> Maybe Int
firstInvalidUtf8 bs = go 0
  where
    n = BS.length bs
    at i = if i < n then Just (BS.index bs i) else Nothing
    inRange lo hi i = case at i of
      Just b -> b >= lo && b <= hi
      Nothing -> False
    -- the lead byte at i needs continuation bytes in the given ranges
    continue i ranges =
      if and [inRange lo hi (i + k) | (k, (lo, hi)) <- zip [1 ..] ranges]
        then go (i + 1 + length ranges)
        else Just i -- the sequence that starts at i is broken
    tail80 = (0x80, 0xBF)
    go i = case at i of
      Nothing -> Nothing
      Just b
        | b < 0x80 -> go (i + 1)
        | b >= 0xC2 && b <= 0xDF -> continue i [tail80]
        | b == 0xE0 -> continue i [(0xA0, 0xBF), tail80]
        | b >= 0xE1 && b <= 0xEC -> continue i [tail80, tail80]
        | b == 0xED -> continue i [(0x80, 0x9F), tail80]
        | b >= 0xEE && b <= 0xEF -> continue i [tail80, tail80]
        | b == 0xF0 -> continue i [(0x90, 0xBF), tail80, tail80]
        | b >= 0xF1 && b <= 0xF3 -> continue i [tail80, tail80, tail80]
        | b == 0xF4 -> continue i [(0x80, 0x8F), tail80, tail80]
        | otherwise -> Just i
