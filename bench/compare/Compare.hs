-- | bench/run's equality check for the IEC benchmarks: every variable a C
-- twin prints (lines NAME=VALUE) against stref's `run --format json`.
--
--   compare C-OUTPUT STREF-JSON
--
-- Names are compared without regard to case (IEC identifiers). A C value
-- is one of: TRUE / FALSE; an integer; REAL#x or LREAL#x (both sides read as
-- binary32 or binary64 and compared bit for bit); T#<n>ms (stref's TIME
-- literal read as a duration); 'text' (a STRING literal as stref prints it,
-- compared character for character). Prints each difference, then a summary line; exits 1 on any
-- difference, a variable stref does not have, or a runtime error of the run.
{-# LANGUAGE LambdaCase #-}
{-# LANGUAGE OverloadedStrings #-}

module Main (main) where

import qualified Data.Aeson as A
import qualified Data.Aeson.Key as K
import qualified Data.Aeson.KeyMap as KM
import qualified Data.ByteString.Lazy as BL
import Data.Char (isDigit, toUpper)
import qualified Data.Map.Strict as M
import Data.Scientific (Scientific, floatingOrInteger, toRealFloat)
import qualified Data.Text as T
import GHC.Float (castDoubleToWord64, castFloatToWord32)
import System.Environment (getArgs)
import System.Exit (exitFailure, exitWith, ExitCode (..))
import System.IO (hPutStrLn, stderr)

main :: IO ()
main = do
  args <- getArgs
  case args of
    [cOut, json] -> run cOut json
    _ -> hPutStrLn stderr "usage: compare C-OUTPUT STREF-JSON" >> exitWith (ExitFailure 2)

run :: FilePath -> FilePath -> IO ()
run cOut json = do
  cLines <- filter (not . null) . lines <$> readFile cOut
  raw <- BL.readFile json
  obj <- case A.decode raw of
    Just (A.Object o) -> pure o
    _ -> hPutStrLn stderr ("compare: " <> json <> " is not a JSON object") >> exitWith (ExitFailure 2)
  let vars = case KM.lookup "vars" obj of
        Just (A.Object vs) -> M.fromList [(map toUpper (K.toString k), v) | (k, v) <- KM.toList vs]
        _ -> M.empty
      runError = case KM.lookup "error" obj of
        Just A.Null -> Nothing
        Nothing -> Nothing
        Just e -> Just e
      checks = [check vars l | l <- cLines]
      bad = [m | Just m <- checks]
      printed = M.fromList [(map toUpper n, ()) | l <- cLines, let n = takeWhile (/= '=') l]
      unprinted = M.size (M.difference vars printed)
  mapM_ putStrLn bad
  case runError of
    Just e -> putStrLn ("stref's run ended with the error " <> show e)
    Nothing -> pure ()
  putStrLn
    ( show (length cLines) <> " variables compared, " <> show (length bad) <> " differ; "
        <> show unprinted <> " of stref's " <> show (M.size vars) <> " variables not printed by the C twin"
    )
  if null bad && runError == Nothing then pure () else exitFailure

check :: M.Map String A.Value -> String -> Maybe String
check vars line =
  case M.lookup (map toUpper name) vars of
    Nothing -> Just (name <> ": not in stref's output (C: " <> cv <> ")")
    Just sv
      | same cv sv -> Nothing
      | otherwise -> Just (name <> ": stref " <> showJ sv <> ", C " <> cv)
  where
    (name, rest) = break (== '=') line
    cv = drop 1 rest

same :: String -> A.Value -> Bool
same c s = case (c, s) of
  ("TRUE", A.Bool b) -> b
  ("FALSE", A.Bool b) -> not b
  ('R' : 'E' : 'A' : 'L' : '#' : x, A.Number n) -> bits32 (read32 x) == bits32 (toRealFloat n)
  ('L' : 'R' : 'E' : 'A' : 'L' : '#' : x, A.Number n) -> bits64 (read64 x) == bits64 (toRealFloat n)
  ('T' : '#' : _, A.String t) -> duration c /= Nothing && duration c == duration (T.unpack t)
  ('\'' : _, A.String t) -> c == T.unpack t
  (_, A.Number n) | Right i <- integral n, [(k, "")] <- reads c -> (k :: Integer) == i
  _ -> False
  where
    bits32 = castFloatToWord32
    bits64 = castDoubleToWord64

integral :: Scientific -> Either Double Integer
integral = floatingOrInteger

-- C's %.9g and %.17g (and stref's shortest round trip) read back exactly:
-- 'read' rounds the decimal correctly. Infinities are written inf / -inf.
read32 :: String -> Float
read32 = readReal

read64 :: String -> Double
read64 = readReal

readReal :: (Read a, RealFloat a) => String -> a
readReal = \case
  "inf" -> 1 / 0
  "-inf" -> -1 / 0
  x -> read (filter (/= '+') x)

-- | A duration literal (T#1h2m3s4ms, T#-5ms, TIME#..., LTIME#...) as a
-- count of nanoseconds; Nothing if it is none.
duration :: String -> Maybe Integer
duration s0 = case break (== '#') (map toUpper s0) of
  (_, '#' : body) -> signed body
  _ -> Nothing
  where
    signed ('-' : b) = negate <$> parts b
    signed b = parts b
    parts "" = Nothing
    parts b = go b
    go "" = Just 0
    go b = do
      let (digits, r) = span (\c -> isDigit c || c == '_') b
          (unit, r') = span (`elem` ("DHMSUN" :: String)) r
      n <- if null digits then Nothing else Just (read (filter (/= '_') digits) :: Integer)
      u <- lookup unit units
      (n * u +) <$> go r'
    units = [("D", 86400 * 10 ^ (9 :: Int)), ("H", 3600 * 10 ^ (9 :: Int)), ("M", 60 * 10 ^ (9 :: Int)), ("S", 10 ^ (9 :: Int)), ("MS", 10 ^ (6 :: Int)), ("US", 1000), ("NS", 1)]

showJ :: A.Value -> String
showJ = map (toEnum . fromEnum) . BL.unpack . A.encode
