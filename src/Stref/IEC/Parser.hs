{-# LANGUAGE MultiWayIf #-}

-- | The parser of an IEC 61131-3 compilation unit (Tecomat manual §3; IEC
-- 61131-3 ed.2 Annex B). Pure and total: every problem is a
-- 'VerificationError' with a stable kind, a position and a message.
--
-- Lexical choices that differ between dialects come from the policy record
-- (nested comments, identifier length); the grammar is one.
module Stref.IEC.Parser
  ( parseUnit
  , parseUnitExpr
  , keywords
  , timeLiteral
  ) where

import Control.Monad (forM_, unless, void, when)
import Data.Char (chr, digitToInt, isAlpha, isAscii, isAsciiLower, isAsciiUpper, isDigit, isHexDigit, isSpace)
import qualified Data.List.NonEmpty as NE
import Data.Maybe (fromMaybe, isJust)
import qualified Data.Set as Set
import Data.Text (Text)
import qualified Data.Text as T
import Stref.IEC.Dialect.MasterTool (operandLocation)
import Stref.IEC.Pragma (preprocessWith)
import Stref.IEC.Syntax
import Stref.IEC.Types (Elem (..), asciiUpper, upperName)
import Stref.Operands (parseOperand)
import Stref.Policy (ElsifKeyword (..), Extensions (..), IdentifierLength (..), NestedComments (..), Policies (..), SourceForm (..), citing)
import Stref.Verification (VerificationError (..))
import Text.Megaparsec hiding (Pos)
import Text.Megaparsec.Char (char, string)

data Issue = Issue Text Text -- kind, message
  deriving (Eq, Ord, Show)

instance ShowErrorComponent Issue where
  showErrorComponent (Issue k m) = T.unpack (k <> ": " <> m)

type Parser = Parsec Issue Text

-- | Parse a whole compilation unit.
parseUnit :: Policies -> FilePath -> Text -> Either VerificationError Unit
parseUnit pol file src0 = do
  -- NX-PRAGMA-13: conditional compilation first, keeping every position
  src <- if codesys pol then preprocessWith (pNestedComments pol) src0 else Right src0
  parseText pol file src

parseText :: Policies -> FilePath -> Text -> Either VerificationError Unit
parseText pol file src = case tooDeep pol src of
  Just off -> Left (VerificationError "nesting-too-deep" (posAt src off) ("the program is nested more than " <> T.pack (show maxNesting) <> " levels deep (parentheses, brackets, operators or statements); split it into simpler parts"))
  Nothing -> runP pol file src (sc pol *> (Unit <$> many (decl pol)) <* eofP)

-- | Deeper nesting than this is refused with @nesting-too-deep@ rather than
-- risking the stack (docs/robustness.md).
maxNesting :: Int
maxNesting = 200

-- | Where the text first nests deeper than 'maxNesting': parentheses and
-- brackets, IF/CASE/FOR/WHILE/REPEAT blocks, runs of prefix operators (NOT,
-- unary minus). Comments and strings are skipped. A linear scan before the
-- parser, so that the parser's recursion stays shallow.
tooDeep :: Policies -> Text -> Maybe Int
tooDeep pol = go 0 0 0 . zip [0 ..] . T.unpack
  where
    openers = ["IF", "CASE", "FOR", "WHILE", "REPEAT"]
    closers = ["END_IF", "END_CASE", "END_FOR", "END_WHILE", "END_REPEAT"]
    go :: Int -> Int -> Int -> [(Int, Char)] -> Maybe Int
    go _ _ _ [] = Nothing
    go depth prefix commentDepth cs@((off, c) : rest)
      | commentDepth > 0 = case cs of
          (_, '*') : (_, ')') : more -> go depth prefix (commentDepth - 1) more
          (_, '(') : (_, '*') : more | pNestedComments pol == Nesting -> go depth prefix (commentDepth + 1) more
          _ -> go depth prefix commentDepth rest
      | otherwise = case cs of
          (_, '(') : (_, '*') : more -> go depth prefix 1 more
          (_, '/') : (_, '/') : more -> go depth prefix 0 (dropWhile ((/= '\n') . snd) more)
          (_, q) : more | q == '\'' || q == '"' -> go depth 0 0 (skipString q more)
          _
            | c == '(' || c == '[' -> deeper 1
            | c == ')' || c == ']' -> go (depth - 1) 0 0 rest
            | c == '-' || c == '+' -> if prefix + 1 > maxNesting then Just off else go depth (prefix + 1) 0 rest
            | isWordChar c ->
                let (w, more) = span (isWordChar . snd) cs
                    u = upperName (T.pack (map snd w))
                 in if
                      | u `elem` openers -> if depth + 1 > maxNesting then Just off else go (depth + 1) 0 0 more
                      | u `elem` closers -> go (depth - 1) 0 0 more
                      | u == "NOT" -> if prefix + 1 > maxNesting then Just off else go depth (prefix + 1) 0 more
                      | otherwise -> go depth 0 0 more
            | isSpace c -> go depth prefix 0 rest
            | otherwise -> go depth 0 0 rest
      where
        deeper k = if depth + k > maxNesting then Just off else go (depth + k) 0 0 rest
    skipString q = \case
      [] -> []
      (_, '$') : _ : more -> skipString q more
      (_, x) : more | x == q -> more
      _ : more -> skipString q more

-- | One expression (for @stref eval@ and the tests).
parseUnitExpr :: Policies -> Text -> Either VerificationError Expr
parseUnitExpr pol src = runP pol "<expression>" src (sc pol *> expr pol <* eofP)

eofP :: Parser ()
eofP = eof <?> "the end of the file"

runP :: Policies -> FilePath -> Text -> Parser a -> Either VerificationError a
runP _ file src p = case runParser p file src of
  Right x -> Right x
  Left bundle -> Left (toError src (NE.head (bundleErrors bundle)))

toError :: Text -> ParseError Text Issue -> VerificationError
toError src = \case
  FancyError off xs -> case [i | ErrorCustom i <- Set.toList xs] of
    (Issue k m : _) -> VerificationError k (posAt src off) m
    [] -> VerificationError "unexpected" (posAt src off) (T.intercalate "; " [T.pack m | ErrorFail m <- Set.toList xs])
  TrivialError off _ expected ->
    let labels = [render i | i <- Set.toList expected]
     in VerificationError "expected-token" (posAt src off) ("expected " <> orList labels <> " instead of " <> describe (T.drop off src))
  where
    render = \case
      Label cs -> T.pack (NE.toList cs)
      Tokens cs -> "'" <> T.pack (NE.toList cs) <> "'"
      EndOfInput -> "the end of the file"
    orList = \case
      [] -> "something else"
      [x] -> x
      xs -> T.intercalate ", " (init xs) <> " or " <> last xs
    describe rest = case T.uncons rest of
      Nothing -> "the end of the file"
      Just (c, r)
        | isWordChar c -> "'" <> T.cons c (T.takeWhile isWordChar r) <> "'"
        | otherwise -> "'" <> T.singleton c <> "'"

posAt :: Text -> Int -> Pos
posAt src off =
  let before = T.take off src
   in Pos (1 + T.count "\n" before) (1 + T.length (T.takeWhileEnd (/= '\n') before))

failAt :: Int -> Text -> Text -> Parser a
failAt off k m = region (setErrorOffset off) (customFailure (Issue k m))

pos :: Parser Pos
pos = do
  sp <- getSourcePos
  pure (Pos (unPos (sourceLine sp)) (unPos (sourceColumn sp)))

------------------------------------------------------------------------------
-- Lexical elements (TC-LEX-*)

isWordChar :: Char -> Bool
isWordChar c = isAsciiUpper c || isAsciiLower c || isDigit c || c == '_'

-- | White space and comments (TC-LEX-5..9): @(* *)@, nested only under
-- @nested-comments = yes@; @//@ to the end of the line.
sc :: Policies -> Parser ()
sc pol = skipMany (void (takeWhile1P (Just "white space") isSpace) <|> blockComment <|> lineComment <|> pragma)
  where
    -- NX-PRAGMA-1, NX-PRAGMA-2, NX-PRAGMA-4: a pragma stands on one line; one
    -- that means nothing to stref is ignored, an attribute is read where a
    -- declaration may carry it, {error '...'} stops the compilation
    pragma
      | pExtensions pol /= ExtensionsCodesys = empty
      | otherwise = do
          off <- getOffset
          body <- try (char '{' *> notFollowedBy (try (many (char ' ') *> caseless "attribute")) *> takeWhileP Nothing (\c -> c /= '}' && c /= '\n') <* char '}')
          when ("error" `T.isPrefixOf` T.toLower (T.stripStart body)) $
            failAt off "pragma-error" ("the program asks for a compilation error: " <> T.strip (T.drop 5 (T.stripStart body)) <> " (NX-PRAGMA-4)")
    lineComment = try (string "//") *> void (takeWhileP Nothing (/= '\n'))
    blockComment = do
      off <- getOffset
      _ <- try (string "(*")
      -- a loop, not a recursion through alternatives: a long comment that
      -- is never closed must not deepen the stack
      let loop :: Int -> Parser ()
          loop depth = do
            _ <- takeWhileP Nothing (\c -> c /= '*' && c /= '(')
            r <- optional (choice [Just False <$ try (string "*)"), Just True <$ try (string "(*"), Nothing <$ anySingle])
            case r of
              Nothing -> failAt off "comment-not-closed" "this comment is never closed by *)"
              Just Nothing -> loop depth
              Just (Just False) -> if depth <= 1 then pure () else loop (depth - 1)
              Just (Just True) -> loop (if pNestedComments pol == Nesting then depth + 1 else depth)
      loop 1

lexeme :: Policies -> Parser a -> Parser a
lexeme pol p = p <* sc pol

symbol :: Policies -> Text -> Parser ()
symbol pol t = lexeme pol (void (string t)) <?> ("'" <> T.unpack t <> "'")

-- | A keyword, in any case (TC-LEX-2), not followed by a word character.
-- | A statement opened at @off@ that its closing keyword @k@ does not
-- close, noticed where a block ends (an END_ keyword, ELSE, ELSIF, UNTIL or
-- the end of the text): the error is at the opener and says where the
-- parser noticed. Anything else found there is the ordinary "expected"
-- error of that place.
notClosed :: Int -> Text -> Text -> Parser a
notClosed off opener k = do
  here <- getSourcePos
  found <- lookAhead (optional (takeWhile1P Nothing isWordChar))
  atEnd' <- atEnd
  let word = upperName <$> found
      endsABlock = atEnd' || maybe False (\w -> "END_" `T.isPrefixOf` w || w `elem` ["ELSE", "ELSIF", "UNTIL"]) word
      at = "line " <> T.pack (show (unPos (sourceLine here))) <> ", column " <> T.pack (show (unPos (sourceColumn here)))
  if endsABlock
    then failAt off "expected-token" ("this " <> opener <> " is not closed: " <> k <> " is missing (the parser reached " <> maybe "the end of the text" (\w -> "'" <> w <> "' at " <> at) found <> " while looking for it)")
    else empty

-- | A word in any case. Keywords, units and attribute names are ASCII,
-- compared here letter by letter without case; megaparsec's string' would
-- fold every character through Unicode's case tables, which was a fifth of
-- the time of a small case.
caseless :: Text -> Parser Text
caseless = tokens (\a b -> T.map asciiUpper a == T.map asciiUpper b)

kw :: Policies -> Text -> Parser ()
kw pol w = lexeme pol (try (caseless w *> notFollowedBy (satisfy isWordChar))) <?> T.unpack w

-- | The keywords of the dialect: IEC's, and CODESYS's under
-- @extensions = codesys@ (NX-LEX-12).
keywordsOf :: Policies -> Set.Set Text
keywordsOf pol
  | codesys pol = keywords `Set.union` codesysKeywords
  | otherwise = keywords

codesysKeywords :: Set.Set Text
codesysKeywords = Set.fromList ["CONTINUE", "JMP", "POINTER", "REFERENCE", "METHOD", "END_METHOD", "PROPERTY", "END_PROPERTY", "EXTENDS", "THIS", "SUPER", "UNION", "END_UNION", "VAR_STAT", "VAR_INST", "PERSISTENT"]

-- | Does the dialect have CODESYS's extensions?
codesys :: Policies -> Bool
codesys pol = pExtensions pol == ExtensionsCodesys

-- | The keywords, which no user name may take (TC-LEX-1).
keywords :: Set.Set Text
keywords =
  Set.fromList
    [ "ACTION", "AND", "ARRAY", "AT", "BY", "CASE", "CONFIGURATION", "CONSTANT", "DO", "ELSE", "ELSIF", "END_ACTION", "END_CASE"
    , "END_CONFIGURATION", "END_FOR", "END_FUNCTION", "END_FUNCTION_BLOCK", "END_IF", "END_PROGRAM", "END_REPEAT", "END_RESOURCE"
    , "END_STRUCT", "END_TYPE", "END_VAR", "END_WHILE", "EXIT", "FALSE", "F_EDGE", "FOR", "FUNCTION", "FUNCTION_BLOCK", "IF"
    , "MOD", "NOT", "OF", "ON", "OR", "PROGRAM", "R_EDGE", "REPEAT", "RESOURCE", "RETAIN", "NON_RETAIN", "RETURN", "STRUCT", "TASK", "THEN", "TO"
    , "TRUE", "TYPE", "UNTIL", "VAR", "VAR_ACCESS", "VAR_CONFIG", "VAR_EXTERNAL", "VAR_GLOBAL", "VAR_INPUT", "VAR_IN_OUT", "VAR_OUTPUT"
    , "VAR_TEMP", "WHILE", "WITH", "XOR", "STRING", "WSTRING"
    ]

-- | An identifier (TC-LEX-11..19): letters, digits and single underscores,
-- not starting with a digit; a national letter or a doubled underscore is
-- @invalid-identifier@.
identifier :: Policies -> Parser (Pos, Name)
identifier pol = lexeme pol $ do
  off <- getOffset
  p <- pos
  w <- lookAhead (takeWhileP Nothing (\c -> isWordChar c || (isAlpha c && not (isAscii c))))
  let invalid msg = takeP Nothing (T.length w) *> failAt off "invalid-identifier" msg
  case T.uncons w of
    Nothing -> empty <?> "a name"
    Just (c, _)
      | isDigit c && T.any isAlpha w && not (T.any (not . isAscii) w) && T.all isWordChar w && not (isNumberText w) ->
          invalid ("the name '" <> w <> "' starts with a digit; a name starts with a letter or an underscore (TC-LEX-11)")
      | isDigit c -> empty <?> "a name"
      | T.any (\x -> isAlpha x && not (isAscii x)) w ->
          invalid ("the name '" <> w <> "' contains a national character; names use the letters A-Z only " <> citing pol ["TC-LEX-12", "NX-LEX-2"])
      | "__" `T.isInfixOf` w ->
          invalid ("the name '" <> w <> "' contains consecutive underscores, which are not allowed " <> citing pol ["TC-LEX-14", "NX-LEX-4"])
      -- MT-LEX-6: a MasterTool name does not end in an underscore
      | pSourceForm pol == MasterToolSource, T.length w > 1, "_" `T.isSuffixOf` w ->
          invalid ("the name '" <> w <> "' ends in an underscore, which MasterTool XE does not allow (MT-LEX-6)")
      | upperName w `Set.member` keywordsOf pol -> empty <?> "a name"
      | otherwise -> do
          _ <- takeP Nothing (T.length w)
          pure (p, significant w)
  where
    -- TC-LEX-16: only the first characters count (policy identifier-length)
    significant w = case pIdentifierLength pol of
      Significant n -> T.take n w
      Unlimited -> w
    -- 2E5 and 1E3 are numbers, not names
    isNumberText w = case T.span isDigit w of
      (_, rest) -> upperName (T.take 1 rest) == "E" && T.all isDigit (T.drop 1 rest) && T.length rest > 1

name :: Policies -> Parser Name
name pol = snd <$> identifier pol

-- | Digits of a base with single underscores between them (TC-LEX-21).
digitsIn :: Int -> Parser Text
digitsIn base = do
  first <- satisfy (isDigitIn base) <?> "a digit"
  rest <- many (try (optional (char '_') *> satisfy (isDigitIn base)))
  pure (T.pack (first : rest))
  where
    isDigitIn b c = isHexDigit c && digitToInt c < b

readIn :: Int -> Text -> Integer
readIn base = T.foldl' (\acc c -> acc * toInteger base + toInteger (digitToInt c)) 0

-- | Integer and real literals (TC-LEX-20..23).
number :: Policies -> Parser Literal
number pol = numberAs pol LInt

-- | A number whose based integers are made by the function given.
numberAs :: Policies -> (Integer -> Literal) -> Parser Literal
numberAs pol basedInt = lexeme pol $ do
  start <- getOffset
  intPart <- digitsIn 10
  based <- optional (try (char '#' *> lookAhead (satisfy isHexDigit)))
  case based of
    Just _ -> do
      let b = readIn 10 intPart
      when (b `notElem` [2, 8, 16]) (fail ("base " <> show b <> " is not one of 2, 8, 16"))
      basedInt . readIn (fromInteger b) <$> digitsIn (fromInteger b)
    Nothing -> do
      frac <- optional (try (char '.' *> digitsIn 10))
      ex <- optional (try (satisfy (`elem` ("eE" :: String)) *> exponentP))
      notFollowedBy (satisfy isWordChar) <?> "the end of the number"
      case (frac, ex) of
        (Nothing, Nothing) -> pure (LInt (readIn 10 intPart))
        _ -> do
          let f = fromMaybe "" frac
              mant = toRational (readIn 10 (intPart <> f)) / (10 ^ T.length f)
              e = fromMaybe 0 ex
          -- decided before the exact value is built: 1.0E999999999 must not
          -- cost time or memory (docs/robustness.md)
          when (abs e > 4000 || T.length intPart + T.length f > 4000) $
            failAt start "value-out-of-limits" "this real literal lies far outside the range of LREAL"
          let
              v = if e >= 0 then mant * 10 ^ e else mant / 10 ^ negate e
           in pure (LReal v (intPart <> maybe "" ("." <>) frac <> maybe "" (\x -> "E" <> T.pack (show x)) ex))
  where
    exponentP = do
      sign <- optional (satisfy (`elem` ("+-" :: String)))
      ds <- digitsIn 10
      let n = readIn 10 ds
      pure (if sign == Just '-' then negate n else n)

-- | A character string (TC-LEX-28..40): @$@ escapes of Tab.3.3 and @$hh@.
stringLit :: Policies -> Char -> Parser Text
stringLit pol q = lexeme pol $ do
  off <- getOffset
  _ <- char q
  go off []
  where
    go off acc = do
      done <- atEnd
      when done (failAt off "string-not-closed" "this string is never closed")
      c <- anySingle
      if
          | c == q -> pure (T.pack (reverse acc))
          | c == '\n' -> failAt off "string-not-closed" "this string is not closed on its line"
          | c == '$' -> do
              eoff <- getOffset
              e <- anySingle
              if
                  | e == '$' -> go off ('$' : acc)
                  | e == '"' && q == '\'' && codesys pol -> failAt eoff "invalid-escape" "$\" is no escape of a STRING (NX-LEX-54, NX-LEX-56)"
                  | e == '\'' || e == '"' -> go off (e : acc)
                  | e `elem` ("Ll" :: String) -> go off ('\n' : acc)
                  | e `elem` ("Nn" :: String) -> go off ('\n' : acc) -- TC-LEX-38: $N is LF
                  | e `elem` ("Pp" :: String) -> go off ('\f' : acc)
                  | e `elem` ("Rr" :: String) -> go off ('\r' : acc)
                  | e `elem` ("Tt" :: String) -> go off ('\t' : acc)
                  -- NX-LEX-58 (open): a WSTRING's character code has four
                  -- hexadecimal digits, as IEC 61131-3's double-byte strings
                  | isHexDigit e && q == '"' -> do
                      es <- count' 0 3 (satisfy isHexDigit)
                      when (length es < 3) (failAt eoff "invalid-escape" "in a WSTRING, $ is followed by four hexadecimal digits or one of $ \" L N P R T (NX-LEX-58)")
                      go off (chr (foldl (\n d -> n * 16 + digitToInt d) 0 (e : es)) : acc)
                  | isHexDigit e -> do
                      e2 <- satisfy isHexDigit <|> failAt eoff "invalid-escape" "$ must be followed by two hexadecimal digits or one of $ ' L N P R T"
                      go off (chr (digitToInt e * 16 + digitToInt e2) : acc)
                  | otherwise -> failAt eoff "invalid-escape" ("$" <> T.singleton e <> " is not a string escape: $ is followed by $, ', L, N, P, R, T or two hexadecimal digits " <> citing pol ["TC-LEX-40", "NX-LEX-54"])
          | otherwise -> go off (c : acc)

-- | Duration literal body after @T#@ (TC-LEX-41, TC-LEX-44): units d h m s ms
-- (also us, ns), any case, fractional values, underscores between units.
durationBody :: Parser Integer
durationBody = snd <$> durationParts

-- | NX-LEX-35..37: in CODESYS's TIME literal the units come in the order
-- d h m s ms, and every unit but the first stays below its limit
-- (T#100S12ms is valid, t#5m68s and t#4ms13d are not).
checkedDuration :: Parser Integer
checkedDuration = do
  off <- getOffset
  (parts, total) <- durationParts
  let units = map fst parts
      limits = [(3600000000000, 24), (60000000000, 60), (1000000000, 60), (1000000, 1000), (1000, 1000), (1, 1000)]
      decreasing = and (zipWith (>) units (drop 1 units))
      withinLimits = and [maybe True (v <) (lookup u limits) | (u, v) <- drop 1 [(u, n `div` u) | (u, n) <- parts]]
  unless decreasing (failAt off "invalid-time-literal" "the units of a TIME literal come in the order d, h, m, s, ms (NX-LEX-35)")
  unless withinLimits (failAt off "invalid-time-literal" "only the first unit of a TIME literal may exceed its limit: h < 24, m < 60, s < 60, ms < 1000 (NX-LEX-36, NX-LEX-37)")
  pure total

-- | The parts of a duration, each as its unit and its nanoseconds, and the total.
durationParts :: Parser ([(Integer, Integer)], Integer)
durationParts = do
  neg <- isJust <$> optional (char '-')
  parts <- some (try part <* optional (char '_'))
  let total = sum (map snd parts)
  pure (parts, if neg then negate total else total)
  where
    part = do
      ds <- digitsIn 10
      frac <- optional (try (char '.' *> digitsIn 10))
      unit <- unitP
      let f = fromMaybe "" frac
          value = toRational (readIn 10 (ds <> f)) / (10 ^ T.length f)
      pure (unit, floor (value * toRational unit))
    unitP :: Parser Integer
    unitP =
      choice
        [ 86400000000000 <$ try (caseless "d" <* notFollowedBy (satisfy isAlpha))
        , 3600000000000 <$ try (caseless "h")
        , 1000000 <$ try (caseless "ms")
        , 60000000000 <$ try (caseless "m" <* notFollowedBy (satisfy (`elem` ("sS" :: String))))
        , 1000 <$ try (caseless "us")
        , 1 <$ try (caseless "ns")
        , 1000000000 <$ try (caseless "s")
        ]

dateBody :: Parser Integer
dateBody = do
  y <- readIn 10 <$> digitsIn 10
  _ <- char '-'
  m <- readIn 10 <$> digitsIn 10
  _ <- char '-'
  d <- readIn 10 <$> digitsIn 10
  when (m < 1 || m > 12 || d < 1 || d > 31) (fail "this is not a valid date")
  pure (daysFromCivil y m d * 86400 * 1000000000)

-- | Days from 1970-01-01 (proleptic Gregorian).
daysFromCivil :: Integer -> Integer -> Integer -> Integer
daysFromCivil y0 m d =
  let y = if m <= 2 then y0 - 1 else y0
      era = y `div` 400
      yoe = y - era * 400
      mp = (m + 9) `mod` 12
      doy = (153 * mp + 2) `div` 5 + d - 1
      doe = yoe * 365 + yoe `div` 4 - yoe `div` 100 + doy
   in era * 146097 + doe - 719468

todBody :: Parser Integer
todBody = do
  h <- readIn 10 <$> digitsIn 10
  _ <- char ':'
  m <- readIn 10 <$> digitsIn 10
  _ <- char ':'
  s <- readIn 10 <$> digitsIn 10
  frac <- optional (try (char '.' *> digitsIn 10))
  when (h > 23 || m > 59 || s > 59) (fail "this is not a valid time of day")
  let f = fromMaybe "" frac
      fracNs = (readIn 10 f * 1000000000) `div` (10 ^ T.length f)
  pure (((h * 60 + m) * 60 + s) * 1000000000 + fracNs)

-- | NX-LEX-50: CODESYS's DT literal may end after the minutes
-- (DT#1998-02-13-14:20).
hoursMinutes :: Parser Integer
hoursMinutes = do
  h <- readIn 10 <$> digitsIn 10
  _ <- char ':'
  m <- readIn 10 <$> digitsIn 10
  when (h > 23 || m > 59) (fail "this is not a valid time of day")
  pure ((h * 60 + m) * 60 * 1000000000)

-- | The text of a duration, date, time-of-day or date-and-time literal, as
-- a conversion from STRING reads it (NX-CONV-33: STRING_TO_TIME('T#127ms')):
-- the whole text, blanks around it ignored, with its prefix in any case and
-- spelling of 'prefixed'; the type the prefix names (TIME for @T#@, LTIME
-- for @LT#@) and the value in nanoseconds. A date and time may leave out
-- the seconds (@DT#1998-02-13-14:20@), as DT_TO_STRING writes it under
-- standard-library = codesys (NX-CONV-30).
timeLiteral :: Text -> Maybe (Elem, Integer)
timeLiteral t = either (const Nothing) Just (runParser (lit <* eof) "" (T.strip t))
  where
    lit = do
      w <- takeWhile1P Nothing isWordChar <* char '#'
      case upperName w of
        u
          | u `elem` ["T", "TIME"] -> (TIME,) <$> durationBody
          | u `elem` ["LT", "LTIME"] -> (LTIME,) <$> durationBody
          | u `elem` ["D", "DATE"] -> (DATE,) <$> dateBody
          | u `elem` ["TOD", "TIME_OF_DAY"] -> (TOD,) <$> todBody
          | u `elem` ["DT", "DATE_AND_TIME"] -> do
              d <- dateBody
              _ <- char '-'
              c <- try todBody <|> hoursMinutes
              pure (DT, d + c)
          | otherwise -> fail "no time literal"

-- | @T#@, @D#@, @TOD#@, @DT#@ in their short and long spellings (TC-LEX-41,
-- TC-LEX-42, TC-LEX-46), and typed literals @INT#5@ (TC-LEX-24), and
-- enumerated values @Type#value@.
prefixed :: Policies -> Parser Expr
prefixed pol = do
  p <- pos
  off <- getOffset
  w <- try (takeWhile1P Nothing isWordChar <* char '#')
  case upperName w of
    u
      | u `elem` ["T", "TIME"] -> lexeme pol (ELit p . LTime <$> (if codesys pol then checkedDuration else durationBody)) <?> "a duration such as 1h2m3s"
      -- NX-LEX-41, NX-TYPE-33: an LTIME, nanoseconds in 64 bits
      | u `elem` ["LT", "LTIME"] -> lexeme pol (ELit p . LTyped "LTIME" . LTime <$> durationBody) <?> "a duration such as 1h2m3s"
      | u `elem` ["D", "DATE"] -> lexeme pol (ELit p . LDate <$> dateBody) <?> "a date such as 2003-06-21"
      | u `elem` ["TOD", "TIME_OF_DAY"] -> lexeme pol (ELit p . LTod <$> todBody) <?> "a time of day such as 06:32:15.08"
      | u `elem` ["DT", "DATE_AND_TIME"] -> lexeme pol (do d <- dateBody; _ <- char '-'; t <- if codesys pol then try todBody <|> hoursMinutes else todBody; pure (ELit p (LDT (d + t)))) <?> "a date and time such as 2003-06-21-11:38:52.35"
      | otherwise -> do
          inner <-
            choice
              [ Left <$> numberAs pol LBits
              , Left . LBool <$> (True <$ kw pol "TRUE" <|> False <$ kw pol "FALSE")
              , Left . LString <$> stringLit pol '\''
              , Left . LWString <$> stringLit pol '"'
              , Left . neg <$> (symbol pol "-" *> number pol)
              , Right <$> name pol
              ]
          case inner of
            Left l -> pure (ELit p (LTyped w l))
            Right v -> do
              when (isDigit (T.head w)) (failAt off "invalid-symbol" "a type name was expected before #")
              pure (EEnum p w v)
  where
    neg = \case
      LInt n -> LInt (negate n)
      LReal r t -> LReal (negate r) ("-" <> t)
      l -> l

-- | A direct address (TC-ADDR-1..5): @%@, a location letter, an optional
-- size letter, numbers separated by dots.
location :: Policies -> Parser Location
location pol | pSourceForm pol == MasterToolSource = lexeme pol $ do
  -- MT-MAP-2, MT-MAP-7, MT-MAP-16: a MasterTool operand, %M0010, %M10.3,
  -- %F0002, %TM0010[5], read by the operand rules of Stref.Operands
  off <- getOffset
  _ <- char '%'
  letters <- takeWhileP Nothing isAsciiLetter
  digits <- takeWhileP Nothing isDigit
  -- MT-MAP-7: spaces may surround a table position; a bit after one is read
  -- with it, for the operand rules to refuse (MT-MAP-16)
  let bit = (\b -> "." <> b) <$> (char '.' *> takeWhile1P Nothing isDigit)
      position = (\p -> "[" <> p <> "]") <$> (char '[' *> takeWhileP Nothing (\c -> isDigit c || c == ' ') <* char ']')
  sub <- option "" (choice [bit, (<>) <$> position <*> option "" bit])
  case parseOperand ("%" <> letters <> digits <> sub) >>= operandLocation of
    Left why -> failAt off "invalid-operand" why
    Right l -> pure l
  where
    isAsciiLetter c = isAsciiUpper c || isAsciiLower c
location pol = lexeme pol $ do
  off <- getOffset
  _ <- char '%'
  area <- toUpperC <$> (satisfy (`elem` ("IQMXYSRiqmxysr" :: String)) <|> failAt off "invalid-operand" "% must be followed by I, Q, M (or Tecomat's X, Y, S, R)")
  -- NX-LEX-61: CODESYS's incomplete %I* and %Q*, which VAR_CONFIG completes
  star <- if codesys pol && area `elem` ("IQ" :: String) then optional (char '*') else pure Nothing
  case star of
    Just _ -> pure (Location ("%" <> T.singleton area <> "*") area '*' [])
    Nothing -> do
      size <- optional (satisfy (`elem` ("XBWDLxbwdl" :: String)))
      nums <- (readIn 10 <$> digitsIn 10) `sepBy1` char '.'
      -- TC-ADDR-1: a bit number is one of the 8 bits of its byte; addresses
      -- are kept within 16 bits so that no address builds a huge number
      case nums of
        [_, b] | b > 7 -> failAt off "value-out-of-limits" ("bit " <> T.pack (show b) <> " does not exist: a byte has the bits 0 to 7")
        _ | any (> 65535) nums || length nums > 2 -> failAt off "value-out-of-limits" "a direct address has a byte number up to 65535 and an optional bit number"
        _ -> pure ()
      let sz = maybe ' ' toUpperC size
          txt = "%" <> T.singleton area <> (if sz == ' ' then "" else T.singleton sz) <> T.intercalate "." (map (T.pack . show) nums)
      pure (Location txt area sz nums)
  where
    toUpperC c = if isAsciiLower c then toEnum (fromEnum c - 32) else c

------------------------------------------------------------------------------
-- Declarations

decl :: Policies -> Parser Decl
decl pol = do
  attrs <- attributes pol
  choice
    [ DTypes . map (\t -> t {tdAttributes = attrs ++ tdAttributes t}) <$> (kw pol "TYPE" *> many (typeDecl pol) <* kw pol "END_TYPE")
    , DGlobals . (\b -> b {vbAttributes = attrs ++ vbAttributes b}) <$> varBlock pol
    , DPou . (\p -> p {pouAttributes = attrs}) <$> pou pol
    , DConfig <$> configuration pol
    , DVarConfig <$> extensionP pol (kw pol "VAR_CONFIG" *> many (configEntry pol) <* kw pol "END_VAR")
    ]
    <?> "TYPE, VAR_GLOBAL, FUNCTION, FUNCTION_BLOCK, PROGRAM or CONFIGURATION"

-- | CODESYS attribute pragmas before a declaration (NX-PRAGMA-5, NX-PRAGMA-6):
-- @{attribute 'name'}@, @{attribute 'name' := 'value'}@, in any case.
attributes :: Policies -> Parser [Attribute]
attributes pol
  | pExtensions pol /= ExtensionsCodesys = pure []
  | otherwise = many $ lexeme pol $ do
      _ <- try (char '{' *> many (char ' ') *> caseless "attribute")
      hspace
      n <- quoted
      hspace
      v <- optional (string ":=" *> hspace *> quoted <* hspace)
      _ <- char '}'
      pure (T.toLower (T.strip n), maybe "" T.strip v)
  where
    hspace = void (takeWhileP Nothing (\c -> c == ' ' || c == '\t'))
    quoted = char '\'' *> takeWhileP Nothing (\c -> c /= '\'' && c /= '\n') <* char '\''

-- | @MainPrg.locioVar1.xLocIn AT %IX1.0 : BOOL;@ (NX-VAR-14)
configEntry :: Policies -> Parser ConfigEntry
configEntry pol = do
  p <- pos
  path <- map snd <$> identifier pol `sepBy1` symbol pol "."
  kw pol "AT"
  l <- location pol
  symbol pol ":"
  t <- typeSpec pol
  symbol pol ";"
  pure (ConfigEntry p path l t)

typeDecl :: Policies -> Parser TypeDecl
typeDecl pol = do
  attrs <- attributes pol
  (p, n) <- identifier pol
  base <- if codesys pol then optional (kw pol "EXTENDS" *> identifier pol) else pure Nothing
  symbol pol ":"
  spec0 <- typeSpec pol
  let spec = maybe spec0 (\(bp, b) -> TSExtends bp b spec0) base
  i <- optional (symbol pol ":=" *> initValue pol)
  -- CODESYS writes END_STRUCT END_TYPE without the ';' (NX-TYPE-51)
  if codesys pol then void (optional (symbol pol ";")) else symbol pol ";"
  pure (TypeDecl p n spec i attrs)

typeSpec :: Policies -> Parser TypeSpec
typeSpec pol = do
  p <- pos
  choice
    [ do
        kw pol "ARRAY"
        symbol pol "["
        -- NX-TYPE-49 (open): the manual says nothing of ARRAY[*]
        star <- if codesys pol then optional (getOffset <* symbol pol "*") else pure Nothing
        forM_ star $ \off -> failAt off "unsupported-type" "ARRAY[*], an array of variable length, is not in the nexto dialect: the manual does not define it (NX-TYPE-49)"
        dims <- ((,) <$> expr pol <* symbol pol ".." <*> expr pol) `sepBy1` symbol pol ","
        symbol pol "]"
        kw pol "OF"
        TSArray p dims <$> typeSpec pol
    , extensionP pol (kw pol "POINTER" *> kw pol "TO" *> (TSPointer p <$> typeSpec pol))
    , otherDialect pol "POINTER TO" (kw pol "POINTER" *> kw pol "TO")
    -- NX-TYPE-81, NX-TYPE-82 (open): REFERENCE is a keyword, but the manual
    -- gives references neither a syntax nor a meaning
    , extensionP pol $ do
        off <- getOffset
        kw pol "REFERENCE"
        failAt off "unsupported-type" "REFERENCE TO is not in the nexto dialect: the manual names references but defines neither their syntax nor their meaning (NX-TYPE-82); POINTER TO is (NX-TYPE-74)"
    , kw pol "STRUCT" *> (TSStruct p . concat <$> many (varDecls pol)) <* kw pol "END_STRUCT"
    , extensionP pol (kw pol "UNION" *> (TSUnion p . concat <$> many (varDecls pol)) <* kw pol "END_UNION")
    , do
        items <- symbol pol "(" *> enumItem pol `sepBy1` symbol pol "," <* symbol pol ")"
        base <- if codesys pol then optional (try (name pol <* notFollowedBy (symbol pol ":" <|> symbol pol ","))) else pure Nothing
        pure (TSEnum p items base)
    , do
        wide <- (False <$ kw pol "STRING") <|> (True <$ kw pol "WSTRING")
        len <- optional ((symbol pol "[" *> expr pol <* symbol pol "]") <|> try (symbol pol "(" *> expr pol <* symbol pol ")"))
        pure (TSString p wide len)
    , do
        n <- name pol
        range <- optional (try (symbol pol "(" *> ((,) <$> expr pol <* symbol pol ".." <*> expr pol) <* symbol pol ")"))
        pure (maybe (TSName p n) (TSSubrange p n) range)
    ]
    <?> "a type"

-- | An enumerated value, with its number under CODESYS (NX-TYPE-62).
enumItem :: Policies -> Parser (Pos, Name, Maybe Expr)
enumItem pol = do
  (p, n) <- identifier pol
  v <- if codesys pol then optional (symbol pol ":=" *> expr pol) else pure Nothing
  pure (p, n, v)

-- | An initial value: an expression, @[...]@ with @n(v)@ repetitions
-- (TC-TYPE-43), or @(field := v, ...)@ (TC-TYPE-44).
initValue :: Policies -> Parser Init
initValue pol = do
  p <- pos
  choice
    [ IArray p <$> (symbol pol "[" *> arrayItem `sepBy` symbol pol "," <* symbol pol "]")
    , try (IStruct p <$> (symbol pol "(" *> structItem `sepBy1` symbol pol "," <* symbol pol ")"))
    , IExpr <$> expr pol
    ]
  where
    -- a repeat count: a number or a constant's name (an expression there
    -- would read CNT((a := 1)) as a call of CNT)
    arrayItem = do
      rep <- optional (try (count <* lookAhead (symbol pol "(")))
      case rep of
        Just n -> do
          symbol pol "("
          v <- optional (initValue pol)
          symbol pol ")"
          pure (Just n, fromMaybe (IArray noPos []) v)
        Nothing -> (Nothing,) <$> initValue pol
    structItem = (,) <$> (name pol <* symbol pol ":=") <*> initValue pol
    count = do
      p <- pos
      ELit p <$> number pol <|> EVar p <$> name pol

sectionP :: Policies -> Parser Section
sectionP pol =
  choice
    [ SecInput <$ kw pol "VAR_INPUT"
    , SecOutput <$ kw pol "VAR_OUTPUT"
    , SecInOut <$ kw pol "VAR_IN_OUT"
    , SecExternal <$ kw pol "VAR_EXTERNAL"
    , SecGlobal <$ kw pol "VAR_GLOBAL"
    , SecTemp <$ kw pol "VAR_TEMP"
    , extensionP pol (SecStat <$ kw pol "VAR_STAT")
    , SecVar <$ kw pol "VAR"
    ]

varBlock :: Policies -> Parser VarBlock
varBlock pol = do
  attrs <- attributes pol
  p <- pos
  sec <- sectionP pol
  quals <- many (choice [Q1 <$ kw pol "CONSTANT", Q2 <$ kw pol "RETAIN", Q0 <$ kw pol "NON_RETAIN", Q3 <$ kw pol "PERSISTENT"])
  ds <- concat <$> many (varDecls pol)
  kw pol "END_VAR"
  pure (VarBlock p sec (Q1 `elem` quals) (Q2 `elem` quals || Q3 `elem` quals) ds (Q3 `elem` quals) attrs)

-- | The qualifiers of a variable block: none, CONSTANT, RETAIN, PERSISTENT
-- (which is also retentive, NX-VAR-20).
data Qualifier = Q0 | Q1 | Q2 | Q3
  deriving (Eq)

-- | @a, b : T := v;@, @x AT %IW2 : WORD;@, @AT %QW2 : WORD := 16#00FF;@ and
-- several located names of one type, @sb1 AT %X0.0, sb2 AT %X0.1 : BOOL;@
-- (TC-ADDR-6, TC-ADDR-9, TC-ADDR-10): one declaration per location.
varDecls :: Policies -> Parser [VarDecl]
varDecls pol = do
  attrs <- attributes pol
  p <- pos
  declarators <- declarator `sepBy` symbol pol ","
  when (null declarators) (void (identifier pol))
  symbol pol ":"
  t <- typeSpec pol
  -- NX-POU-35: an FB instance's FB_Init inputs at its declaration
  args <- if codesys pol then option [] (try (symbol pol "(" *> arg pol `sepBy1` symbol pol "," <* symbol pol ")")) else pure []
  edge <- optional (REdge <$ kw pol "R_EDGE" <|> FEdge <$ kw pol "F_EDGE")
  i <- optional (symbol pol ":=" *> initValue pol)
  symbol pol ";"
  let plain = [n | (Just n, Nothing) <- declarators]
      located = [(n, l) | (n, Just l) <- declarators]
  pure $
    [VarDecl p plain Nothing t edge i attrs args | not (null plain)]
      ++ [VarDecl p (maybe [] (: []) n) (Just l) t edge i attrs args | (n, l) <- located]
  where
    declarator =
      ((,) <$> (Just <$> identifier pol) <*> optional (kw pol "AT" *> location pol))
        <|> ((Nothing,) . Just <$> (kw pol "AT" *> location pol))

pou :: Policies -> Parser Pou
pou pol = do
  p <- pos
  (kind, endKw) <-
    choice
      [ (KFunctionBlock, "END_FUNCTION_BLOCK") <$ kw pol "FUNCTION_BLOCK"
      , (KFunction, "END_FUNCTION") <$ kw pol "FUNCTION"
      , (KProgram, "END_PROGRAM") <$ kw pol "PROGRAM"
      ]
  n <- name pol
  result <- if kind == KFunction then Just <$> (symbol pol ":" *> typeSpec pol) else pure Nothing
  base <- if kind == KFunctionBlock then optional (extensionP pol (extendsClause pol)) else pure Nothing
  blocks <- many (varBlock pol)
  before <- many (member pol)
  body <- statements pol
  after <- many (member pol)
  e <- pos
  kw pol endKw
  pure (Pou p kind n result blocks body e base (before ++ after) [])

-- | @EXTENDS A@; a second base is @multiple-inheritance@ (NX-POU-47).
extendsClause :: Policies -> Parser (Pos, Name)
extendsClause pol = do
  kw pol "EXTENDS"
  b <- identifier pol
  off <- getOffset
  more <- optional (symbol pol ",")
  case more of
    Just () -> failAt off "multiple-inheritance" "a function block extends one function block only (NX-POU-47)"
    Nothing -> pure b

-- | Under @extensions = codesys@ only.
-- | A construct of CODESYS (the nexto dialect) met where the extensions
-- are off: the error says which dialect has it. It is recognised only in
-- its full form (@CONTINUE;@), so that the word stays a name otherwise.
otherDialect :: Policies -> Text -> Parser () -> Parser a
otherDialect pol what q
  | codesys pol = empty
  | otherwise = do
      off <- getOffset
      -- consumed before failing, so that no later alternative reads it as a name
      _ <- lookAhead (try q)
      q
      failAt off "expected-token" (what <> " is a CODESYS extension, not part of this dialect: --dialect nexto has it (policy extensions=codesys)")

extensionP :: Policies -> Parser a -> Parser a
extensionP pol q = if codesys pol then q else empty

-- | A METHOD, PROPERTY or ACTION written inside its POU (docs/nexto.md).
member :: Policies -> Parser Member
member pol = extensionP pol (attributes pol *> choice [method, property, action])
  where
    specifiers = many (choice [kw pol w | w <- ["PUBLIC", "PRIVATE", "PROTECTED", "INTERNAL", "FINAL", "ABSTRACT"]])
    method = do
      p <- pos
      kw pol "METHOD"
      _ <- specifiers
      n <- name pol
      result <- optional (symbol pol ":" *> typeSpec pol)
      blocks <- many (varBlock pol)
      body <- statements pol
      kw pol "END_METHOD"
      pure (MMethod (Method p n result blocks body))
    property = do
      p <- pos
      kw pol "PROPERTY"
      _ <- specifiers
      n <- name pol
      symbol pol ":"
      t <- typeSpec pol
      getter <- optional (accessor "GET" "END_GET")
      setter <- optional (accessor "SET" "END_SET")
      kw pol "END_PROPERTY"
      pure (MProperty (Property p n t getter setter))
    accessor open close = do
      kw pol open
      blocks <- many (varBlock pol)
      body <- statements pol
      kw pol close
      pure (blocks, body)
    action = do
      p <- pos
      kw pol "ACTION"
      n <- name pol
      _ <- optional (symbol pol ":")
      body <- statements pol
      kw pol "END_ACTION"
      pure (MAction p n body)

configuration :: Policies -> Parser Configuration
configuration pol = do
  p <- pos
  kw pol "CONFIGURATION"
  n <- name pol
  globals <- many (varBlock pol)
  resources <- some (resource pol) <|> ((: []) <$> resourceBody pol p "")
  kw pol "END_CONFIGURATION"
  pure (Configuration p n globals resources)

resource :: Policies -> Parser Resource
resource pol = do
  p <- pos
  kw pol "RESOURCE"
  n <- name pol
  _ <- optional (kw pol "ON" *> name pol)
  r <- resourceBody pol p n
  kw pol "END_RESOURCE"
  pure r

resourceBody :: Policies -> Pos -> Name -> Parser Resource
resourceBody pol p n = do
  globals <- many (varBlock pol)
  items <- many (Left <$> task <|> Right <$> program)
  pure (Resource p n Nothing globals [t | Left t <- items] [g | Right g <- items])
  where
    task = do
      tp <- pos
      kw pol "TASK"
      tn <- name pol
      props <- option [] (symbol pol "(" *> ((,) <$> name pol <* symbol pol ":=" <*> expr pol) `sepBy` symbol pol "," <* symbol pol ")")
      symbol pol ";"
      pure (Task tp tn props)
    program = do
      pp <- pos
      kw pol "PROGRAM"
      inst <- name pol
      t <- optional (kw pol "WITH" *> name pol)
      symbol pol ":"
      ty <- name pol
      args <- option [] (symbol pol "(" *> arg pol `sepBy` symbol pol "," <* symbol pol ")")
      symbol pol ";"
      pure (ProgramConfig pp inst t ty args)

------------------------------------------------------------------------------
-- Statements (TC-STMT-*)

-- | Keywords that end a statement list.
enders :: [Text]
enders = ["END_IF", "ELSIF", "ELSE", "END_CASE", "END_FOR", "END_WHILE", "UNTIL", "END_REPEAT", "END_FUNCTION", "END_FUNCTION_BLOCK", "END_PROGRAM", "METHOD", "END_METHOD", "PROPERTY", "ACTION", "END_ACTION", "END_GET", "END_SET"]

atEnder :: Policies -> Parser Bool
atEnder pol = isJust <$> optional (lookAhead (choice (map (kw pol) enders) <|> elsifKw pol))

-- | ELSIF, and ELSEIF where policy @elsif-keyword@ accepts it.
elsifKw :: Policies -> Parser ()
elsifKw pol = case pElsifKeyword pol of
  ElsifOnly -> kw pol "ELSIF"
  ElsifAndElseif -> kw pol "ELSIF" <|> kw pol "ELSEIF"

statements :: Policies -> Parser [Stmt]
statements pol = go []
  where
    -- a loop: ten thousand statements must not deepen the stack
    go acc = do
      e <- atEnder pol
      done <- atEnd
      if e || done then pure (reverse acc) else statement pol >>= \st -> go (st : acc)

-- | Statements of a CASE arm: they end where the next labels start.
caseStatements :: Policies -> Parser [Stmt]
caseStatements pol = go []
  where
    go acc = do
      e <- atEnder pol
      l <- isJust <$> optional (lookAhead (try (caseLabels pol *> symbol pol ":" *> notFollowedBy (char '='))))
      if e || l then pure (reverse acc) else statement pol >>= \st -> go (st : acc)

statement :: Policies -> Parser Stmt
statement pol = do
  p <- pos
  choice
    [ SEmpty p <$ symbol pol ";"
    , ifStmt p
    , caseStmt p
    , forStmt p
    , whileStmt p
    , repeatStmt p
    , SExit p <$ kw pol "EXIT" <* symbol pol ";"
    , SReturn p <$ kw pol "RETURN" <* symbol pol ";"
    , extension (SContinue p <$ kw pol "CONTINUE" <* symbol pol ";")
    , otherDialect pol "CONTINUE" (kw pol "CONTINUE" *> symbol pol ";")
    , otherDialect pol "JMP" (kw pol "JMP" *> name pol *> symbol pol ";")
    , extension (SJump p <$> (kw pol "JMP" *> name pol) <* symbol pol ";")
    , extension (try (SLabel p <$> name pol <* symbol pol ":" <* notFollowedBy (char '=')))
    , simple p
    ]
    <?> "a statement"
  where
    ifStmt p = do
      off <- getOffset
      kw pol "IF"
      c <- expr pol
      kw pol "THEN"
      b <- statements pol
      elsifs <- many ((,) <$> (elsifKw pol *> expr pol <* kw pol "THEN") <*> statements pol)
      els <- option [] (kw pol "ELSE" *> statements pol)
      closing off "IF" "END_IF"
      endSemi
      pure (SIf p ((c, b) : elsifs) els)
    caseStmt p = do
      off <- getOffset
      kw pol "CASE"
      sel <- expr pol
      kw pol "OF"
      arms <- many ((,) <$> (caseLabels pol <* symbol pol ":") <*> caseStatements pol)
      els <- option [] (kw pol "ELSE" *> statements pol)
      closing off "CASE" "END_CASE"
      endSemi
      pure (SCase p sel arms els)
    forStmt p = do
      off <- getOffset
      kw pol "FOR"
      v <- name pol
      symbol pol ":="
      s <- expr pol
      kw pol "TO"
      e <- expr pol
      st <- optional (kw pol "BY" *> expr pol)
      kw pol "DO"
      b <- statements pol
      closing off "FOR" "END_FOR"
      endSemi
      pure (SFor p v s e st b)
    whileStmt p = do
      off <- getOffset
      kw pol "WHILE"
      c <- expr pol
      kw pol "DO"
      b <- statements pol
      closing off "WHILE" "END_WHILE"
      endSemi
      pure (SWhile p c b)
    repeatStmt p = do
      off <- getOffset
      kw pol "REPEAT"
      b <- statements pol
      closing off "REPEAT" "UNTIL"
      c <- expr pol
      _ <- optional (symbol pol ";") -- TC-ERRATA-4: Tab.3.24 writes `UNTIL i < 20;`
      kw pol "END_REPEAT"
      endSemi
      pure (SRepeat p b c)
    extension q = if codesys pol then q else empty
    -- the keyword that closes a statement; missing where an enclosing
    -- block ends, the error is at the statement it should close (after
    -- 'optional': an error of '<|>' would lose to the later one of 'kw')
    closing off opener k = optional (kw pol k) >>= maybe (notClosed off opener k) pure
    -- NX-STMT-2: CODESYS does not require the ';' after END_IF and the like
    endSemi = if codesys pol then void (optional (symbol pol ";")) else symbol pol ";"
    setOrReset = (OpSet <$ lexeme pol (try (caseless "S="))) <|> (OpReset <$ lexeme pol (try (caseless "R=")))
    assignOp = (OpAssign <$ symbol pol ":=") <|> extension setOrReset
    -- NX-STMT-6..9: further targets of a chain, each before its operator
    chain acc = do
      more <- if codesys pol then optional (try ((,) <$> variable pol <*> assignOp)) else pure Nothing
      case more of
        Just t -> chain (t : acc)
        Nothing -> pure (reverse acc)
    simple p = do
      target <- variable pol
      choice
        [ case target of
            EInvoke _ callee args -> SCall p callee args <$ symbol pol ";"
            _ -> empty
        , do
            op <- assignOp
            rest <- chain []
            v <- expr pol
            symbol pol ";"
            pure $ case (op, rest) of
              (OpAssign, []) -> SAssign p target v
              _ -> SChain p ((target, op) : rest) v
        , do
            args <- symbol pol "(" *> arg pol `sepBy` symbol pol "," <* symbol pol ")"
            symbol pol ";"
            pure (SCall p target args)
        ]

caseLabels :: Policies -> Parser [CaseLabel]
caseLabels pol = label `sepBy1` symbol pol ","
  where
    label = do
      a <- caseValue
      r <- optional (symbol pol ".." *> caseValue)
      pure (maybe (CaseValue a) (CaseRange a) r)
    caseValue = do
      p <- pos
      -- a based number (16#1F) before a typed value (Color#red)
      choice
        [ ELit p <$> number pol
        , do
            symbol pol "-"
            l <- number pol
            pure (EUn p UNeg (ELit p l))
        , prefixed pol
        , EVar p <$> name pol
        ]

arg :: Policies -> Parser Arg
arg pol = do
  p <- pos
  formal <- optional (try ((,) <$> name pol <*> (True <$ symbol pol ":=" <|> False <$ symbol pol "=>")))
  case formal of
    Just (n, True) -> ArgInput p n <$> expr pol
    Just (n, False) -> ArgOutput p n <$> variable pol
    Nothing -> ArgPositional <$> expr pol

------------------------------------------------------------------------------
-- Expressions: the priorities of Tab.3.23 (TC-OP-1), equal priorities from
-- left to right (TC-OP-3)

expr :: Policies -> Parser Expr
expr pol =
  level [(BOr, kw pol "OR")] $
    level [(BXor, kw pol "XOR")] $
      level [(BAnd, kw pol "AND"), (BAnd, op "&" "")] $
        level [(BEq, op "=" ">"), (BNe, op "<>" "")] $
          level [(BLe, op "<=" ""), (BGe, op ">=" ""), (BLt, op "<" ">="), (BGt, op ">" "=")] $
            level [(BAdd, op "+" ""), (BSub, op "-" "")] $
              level [(BMul, op "*" "*"), (BDiv, op "/" ""), (BMod, kw pol "MOD")] (unary pol)
  where
    -- a symbol not followed by one of the characters that would make it another
    op t notNext = lexeme pol (try (string t <* notFollowedBy (satisfy (`elem` T.unpack notNext)))) *> pure () <?> ("'" <> T.unpack t <> "'")
    level ops next = next >>= rest
      where
        rest acc = do
          m <- optional (choice [o <$ sym | (o, sym) <- ops])
          case m of
            Nothing -> pure acc
            Just o -> do
              r <- next
              rest (EBin (exprPos acc) o acc r)

-- | Unary minus and NOT bind less tightly than @**@ (Tab.3.23).
unary :: Policies -> Parser Expr
unary pol = do
  p <- pos
  choice
    [ EUn p UNeg <$> (symbol pol "-" *> unary pol)
    , EUn p UPlus <$> (symbol pol "+" *> unary pol)
    , EUn p UNot <$> (kw pol "NOT" *> unary pol)
    , power pol
    ]

-- | @**@, left-associative (TC-OP-4); its right operand may carry a sign.
power :: Policies -> Parser Expr
power pol = do
  b <- primary pol
  rest b
  where
    rest acc = do
      m <- optional (symbol pol "**")
      case m of
        Nothing -> pure acc
        Just () -> do
          e <- powerOperand
          rest (EBin (exprPos acc) BPow acc e)
    powerOperand = do
      p <- pos
      (EUn p UNeg <$> (symbol pol "-" *> powerOperand)) <|> primary pol

primary :: Policies -> Parser Expr
primary pol = do
  p <- pos
  choice
    [ do
        e <- symbol pol "(" *> expr pol <* symbol pol ")"
        -- NX-TYPE-77: (p + 7)^
        deref <- if codesys pol then optional (lookAhead (symbol pol "^")) else pure Nothing
        maybe (pure e) (const (postfix pol e)) deref
    , ELit p <$> number pol
    , ELit p . LBool <$> (True <$ kw pol "TRUE" <|> False <$ kw pol "FALSE")
    , ELit p . LString <$> stringLit pol '\''
    , ELit p . LWString <$> stringLit pol '"'
    , ELocated p <$> location pol
    , prefixed pol
      -- a name before '(' is a call: committed there, so that a malformed
      -- argument list is not parsed again as a variable's (exponential in
      -- the nesting of calls)
    , ECall p <$> try (name pol <* lookAhead (symbol pol "(")) <*> (symbol pol "(" *> arg pol `sepBy` symbol pol "," <* symbol pol ")")
      -- AND, OR, XOR and MOD are also the names of standard functions (Tab.3.14, Tab.3.16)
    , try (ECall p <$> choice [w <$ kw pol w | w <- ["AND", "OR", "XOR", "MOD"]] <*> (symbol pol "(" *> arg pol `sepBy` symbol pol "," <* symbol pol ")"))
    , variable pol
    ]
    <?> "an expression"

-- | A variable: a name, then fields and indices (TC-TYPE-38, TC-TYPE-42);
-- under CODESYS also @THIS@, @SUPER@, @.name@, dereferences @^@ and calls
-- of what the path names (@inst.m(..)@).
variable :: Policies -> Parser Expr
variable pol = do
  p <- pos
  base <-
    choice
      [ ELocated p <$> location pol
      , extensionP pol (EThis p <$ kw pol "THIS")
      , extensionP pol (ESuper p <$ kw pol "SUPER")
      , extensionP pol (EGlobalScope p <$> (try (symbol pol "." *> lookAhead (satisfy isAsciiLetterOrUnderscore)) *> name pol))
      , EVar p <$> name pol
      ]
  postfix pol base
  where
    isAsciiLetterOrUnderscore c = isAsciiUpper c || isAsciiLower c || c == '_'

-- | Fields, indices, dereferences and calls after a variable (or after a
-- parenthesised pointer expression: @(p + 2)^@).
postfix :: Policies -> Expr -> Parser Expr
postfix pol = go
  where
    go acc = do
      p <- pos
      m <-
        optional $
          choice
            [ PIndex <$> (symbol pol "[" *> expr pol `sepBy1` symbol pol "," <* symbol pol "]")
            , -- NX-OP-92: x.3 and x.%X3, a bit of an integer
              PBit <$> extensionP pol (try (lexeme pol (char '.' *> optional (caseless "%X") *> (readIn 10 <$> digitsIn 10))))
            , PField <$> try (symbol pol "." *> name pol)
            , PDeref <$ extensionP pol (symbol pol "^")
            , PCall <$> extensionP pol (try (symbol pol "(" *> arg pol `sepBy` symbol pol "," <* symbol pol ")") <* notFollowedBy (symbol pol ":="))
            ]
      case m of
        Nothing -> pure acc
        Just (PIndex ix) -> go (EIndex p acc ix)
        Just (PBit b) -> go (EBit p acc b)
        Just (PField f) -> go (EField p acc f)
        Just PDeref -> go (EDeref p acc)
        Just (PCall args) -> go (EInvoke p acc args)

data Postfix = PIndex [Expr] | PBit Integer | PField Name | PDeref | PCall [Arg]
